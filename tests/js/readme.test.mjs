// The README as a user reads it: its commands run as written from the
// repository root (the CLI quick start with the native build, the
// JavaScript quick start with the package as `cdt3d`), it stays short, and
// its two commands are the ones CI runs.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { describe, test } from 'node:test';

import { repoRoot, requireNativeCli, skipNative } from './support.mjs';

const readme = readFileSync(path.join(repoRoot, 'README.md'), 'utf8');

// The fenced blocks of the given language in the section headed `heading`.
function blocks(heading, lang) {
  const start = readme.indexOf(`\n## ${heading}\n`);
  assert.ok(start >= 0, `README has a section "${heading}"`);
  const next = readme.indexOf('\n## ', start + 1);
  const section = readme.slice(start, next < 0 ? undefined : next);
  const found = [];
  const re = new RegExp('```' + lang + '\\n([\\s\\S]*?)```', 'g');
  for (const m of section.matchAll(re)) found.push(m[1]);
  assert.ok(found.length > 0, `"${heading}" has a ${lang} block`);
  return found;
}

const scratch = path.join(repoRoot, '.build', 'readme');

describe('README', () => {
  test('is short, and its two commands are npm start and npm test, the latter what CI runs', () => {
    assert.ok(readme.split('\n').length < 200, 'README.md has fewer than 200 lines');
    const [two] = blocks('Two commands', 'sh');
    const commands = two.split('\n').filter(Boolean).map((l) => l.replace(/#.*/, '').trim());
    assert.deepEqual(commands, ['npm start', 'npm test']);
    const ci = readFileSync(path.join(repoRoot, '.ci', 'run'), 'utf8');
    assert.match(ci, /^npm test$/m);
  });

  test('the CLI quick start runs as written', { skip: skipNative && 'CDT3D_SKIP_NATIVE=1' }, () => {
    requireNativeCli();
    mkdirSync(scratch, { recursive: true });
    const lines = blocks('Quick start: the CLI', 'sh').join('\n').split('\n').filter((l) => l.trim());
    assert.ok(lines.length >= 4);
    for (const line of lines) {
      const [cmd, ...args] = line.replace(/\s+#.*$/, '').trim().split(/\s+/);
      assert.equal(cmd, '.build/native/core/cdt3d', line);
      const r = spawnSync(path.join(repoRoot, cmd), args, { cwd: repoRoot, encoding: 'utf8', maxBuffer: 64 << 20 });
      assert.equal(r.status, 0, `${line}\n${r.stderr}`);
    }
  });

  test('the JavaScript quick start runs as written', () => {
    const [code] = blocks('Quick start: JavaScript', 'js');
    mkdirSync(scratch, { recursive: true });
    // Inside the repository, so that `cdt3d` resolves to the workspace package.
    const file = path.join(scratch, 'quickstart.mjs');
    writeFileSync(file, code);
    const r = spawnSync(process.execPath, [file], { cwd: repoRoot, encoding: 'utf8' });
    assert.equal(r.status, 0, r.stderr);
    assert.match(r.stdout, /^\d+ tets, \d+ Steiner points$/m);
    assert.match(r.stdout, /^\d+ flat edges merged into \d+ facets$/m);
    assert.match(r.stdout, /^self-intersection /m);
  });
});
