// Vite config of the cdt3d browser demo: `npx vite web` (dev server),
// `npx vite build web` (static build in web/dist, works from any sub-path).
import { existsSync, readFileSync, statSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { defineConfig } from 'vite';

const here = fileURLToPath(new URL('.', import.meta.url));

// The page imports the package's worker helper as users do ('cdt3d/worker');
// until wasm/package.json exports it, point the name at the file.
const pkg = JSON.parse(readFileSync(new URL('../wasm/package.json', import.meta.url), 'utf8'));
const alias = pkg.exports?.['./worker']
  ? {}
  : { 'cdt3d/worker': fileURLToPath(new URL('../wasm/worker.js', import.meta.url)) };

const ISOLATION = {
  'Cross-Origin-Opener-Policy': 'same-origin',
  'Cross-Origin-Embedder-Policy': 'require-corp',
};

// The dev server serves the package's built files (wasm/dist) as they are.
// Vite would otherwise add an import statement to cdt3d.worker.js, the
// two-thread module's classic worker script, which then fails to load.
const dist = fileURLToPath(new URL('../wasm/dist/', import.meta.url));
const rawDist = {
  name: 'cdt3d-raw-dist',
  configureServer(server) {
    server.middlewares.use((req, res, next) => {
      const pathname = decodeURIComponent(new URL(req.url, 'http://x').pathname);
      const file = pathname.startsWith('/@fs/') ? pathname.slice('/@fs'.length) : '';
      if (!file.startsWith(dist) || file.includes('..') || !existsSync(file) || !statSync(file).isFile()) return next();
      res.writeHead(200, {
        'content-type': file.endsWith('.wasm') ? 'application/wasm' : 'text/javascript; charset=utf-8',
        ...ISOLATION,
      });
      res.end(readFileSync(file));
    });
  },
};

export default defineConfig({
  plugins: [rawDist],
  root: here,
  base: './',
  publicDir: 'public',
  // Keep cdt3d out of dependency pre-bundling, so its .js stays next to its
  // .wasm (found with new URL(..., import.meta.url)) and its worker script.
  resolve: { alias },
  optimizeDeps: { exclude: ['cdt3d'] },
  worker: { format: 'es' },
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    target: 'es2022',
    chunkSizeWarningLimit: 1500,
    // Never inline the package's pthread worker script (3 KB) as a data: URL:
    // a worker from a data: URL has an opaque origin and cannot import the
    // module script it runs, so the two-thread module would not start.
    assetsInlineLimit: (file) => (file.endsWith('.worker.js') ? false : undefined),
  },
  // Cross-origin isolation gives the page SharedArrayBuffer, so the package
  // loads its two-thread module (a static host needs the same two headers:
  // README.md).
  server: { host: '127.0.0.1', headers: ISOLATION },
  preview: { host: '127.0.0.1', headers: ISOLATION },
});
