// Vite config of the cdt3d browser demo: `npx vite web` (dev server),
// `npx vite build web` (static build in web/dist, works from any sub-path).
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { defineConfig } from 'vite';

const here = fileURLToPath(new URL('.', import.meta.url));

// The page imports the package's worker helper as users do ('cdt3d/worker');
// until wasm/package.json exports it, point the name at the file.
const pkg = JSON.parse(readFileSync(new URL('../wasm/package.json', import.meta.url), 'utf8'));
const alias = pkg.exports?.['./worker']
  ? {}
  : { 'cdt3d/worker': fileURLToPath(new URL('../wasm/worker.js', import.meta.url)) };

export default defineConfig({
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
  },
  server: { host: '127.0.0.1' },
  preview: { host: '127.0.0.1' },
});
