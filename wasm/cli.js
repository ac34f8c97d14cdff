#!/usr/bin/env node
// `npx cdt3d mesh MODEL [-o PREFIX] [--format node|vtk|mesh] [--keep-hull]
//  [--validate] [--stats] [--json] [-q]` and `npx cdt3d info MODEL [--json]`:
// the native CLI's commands, switches and exit codes (0 success, 1 input or
// meshing error, 2 usage error), run on the WebAssembly build.
import { readFileSync, writeFileSync } from 'node:fs';

import { Cdt3dError, createCdt3d } from './node.js';

const EXIT_OK = 0;
const EXIT_ERROR = 1;
const EXIT_USAGE = 2;

const USAGE = `usage: cdt3d <command> [arguments]

commands:
  info MODEL [--json]      read a PLC and print its summary
  mesh MODEL [-o PREFIX] [--format node|vtk|mesh] [--keep-hull] [--validate]
             [--stats] [--json] [-q] [--merge] [--paper-degeneracy] [--no-intersection-check]
             [--stop-after PHASE]
                           constrained Delaunay tetrahedralization of MODEL

MODEL: .stl (ASCII/binary) .off .obj .ply .poly .smesh
exit codes: 0 success, 1 input or meshing error, 2 usage error
`;

function usage(message) {
  if (message) process.stderr.write(`cdt3d: ${message}\n`);
  process.stderr.write(USAGE);
  return EXIT_USAGE;
}

function parse(args) {
  const opts = { input: null, prefix: null, format: 'node', json: false, quiet: false, stats: false, tet: {} };
  for (let i = 0; i < args.length; ++i) {
    const a = args[i];
    if (a === '--json') opts.json = true;
    else if (a === '-q') opts.quiet = true;
    else if (a === '--stats') opts.stats = true;
    else if (a === '--keep-hull') opts.tet.keepConvexHull = true;
    else if (a === '--validate') opts.tet.validate = true;
    else if (a === '--no-intersection-check') opts.tet.checkIntersections = false;
    else if (a === '--merge') opts.tet.mergeCoplanarFacets = true;
    else if (a === '--paper-degeneracy') opts.tet.degeneracy = 'paper';
    else if ((a === '-o' || a === '--format' || a === '--stop-after') && i + 1 < args.length) {
      const v = args[++i];
      if (a === '-o') opts.prefix = v;
      else if (a === '--format') opts.format = v;
      else opts.tet.stopAfter = v;
    } else if (!a.startsWith('-') && opts.input === null) opts.input = a;
    else return { error: `unexpected argument '${a}'` };
  }
  if (opts.input === null) return { error: 'no MODEL given' };
  if (!['node', 'vtk', 'mesh'].includes(opts.format)) return { error: `unknown format '${opts.format}'` };
  if (opts.tet.stopAfter !== undefined && !['delaunay', 'segments', 'degeneracy', 'facets'].includes(opts.tet.stopAfter)) {
    return { error: `--stop-after takes delaunay, segments, degeneracy or facets, not '${opts.tet.stopAfter}'` };
  }
  return opts;
}

function printError(e, json) {
  const err = e instanceof Cdt3dError ? e : new Cdt3dError('io', e.message ?? String(e));
  if (json) process.stdout.write(`${JSON.stringify({ ok: false, error: err.toJSON() })}\n`);
  else {
    const where = [['facet', err.facet], ['other facet', err.otherFacet], ['segment', err.segment], ['vertex', err.vertex], ['record', err.record]]
      .filter(([, v]) => v >= 0).map(([k, v]) => `${k} ${v}`).join(', ');
    const file = err.file ? `${err.file}${err.line >= 0 ? `:${err.line}` : ''}: ` : '';
    process.stderr.write(`cdt3d: ${file}${err.message}${where ? ` (${where})` : ''} [${err.code}]\n`);
  }
  return EXIT_ERROR;
}

function table(file, s, validated) {
  const lines = [
    file,
    `  Input points:              ${s.inputPoints}`,
    `  Input facets:              ${s.inputFacets}`,
    `  Input segments:            ${s.inputSegments}`,
    `  Mesh points:               ${s.points}`,
    `  Mesh tetrahedra:           ${s.tets}`,
    `  Mesh constrained faces:    ${s.faces}`,
    `  Steiner points:            ${s.steinerSegment + s.steinerFacet + s.steinerVolume} (segments ${s.steinerSegment}, facets ${s.steinerFacet} of which ${s.facetSplits} in failed facet regions, volume ${s.steinerVolume})`,
    `  Flat tetrahedra:           ${s.flatTets} in the output, ${s.flatFlips} removed by flips`,
    `  Time (ms):                 read ${s.msRead.toFixed(1)}, delaunay ${s.msDelaunay.toFixed(1)}, segments ${s.msSegments.toFixed(1)}, degeneracy ${s.msDegeneracy.toFixed(1)}, facets ${s.msFacets.toFixed(1)}, carve ${s.msCarve.toFixed(1)}, total ${s.msTotal.toFixed(1)}`,
  ];
  if (validated) lines.push('  Validation:                passed');
  return `${lines.join('\n')}\n`;
}

async function main(argv) {
  const [command, ...rest] = argv;
  if (command === undefined) return usage();
  if (command === '-h' || command === '--help') {
    process.stdout.write(USAGE);
    return EXIT_OK;
  }
  if (command !== 'mesh' && command !== 'info') return usage(`unknown command '${command}'`);
  const opts = parse(rest);
  if (opts.error) return usage(opts.error);
  const cdt = await createCdt3d();
  try {
    const bytes = readFileSync(opts.input);
    if (command === 'info') {
      const info = cdt.readPlc(bytes, opts.input);
      process.stdout.write(opts.json ? `${JSON.stringify({ ok: true, ...info })}\n` : `${Object.entries(info).map(([k, v]) => `${k}: ${v}`).join('\n')}\n`);
      return EXIT_OK;
    }
    const r = cdt.tetrahedralize({ bytes, fileName: opts.input }, opts.tet);
    if (opts.prefix !== null) {
      const exts = opts.format === 'node' ? (opts.tet.stopAfter ? ['node', 'ele'] : ['node', 'ele', 'face']) : [opts.format];
      for (const ext of exts) writeFileSync(`${opts.prefix}.${ext}`, cdt.write(r, ext));
    }
    if (opts.json) process.stdout.write(`${JSON.stringify({ ok: true, phase: opts.tet.stopAfter ?? 'done', ...r.stats, valid: opts.tet.validate ? true : null })}\n`);
    else if (!opts.quiet) process.stdout.write(table(opts.input, r.stats, opts.tet.validate));
    return EXIT_OK;
  } catch (e) {
    if (e?.code === 'ENOENT' || e?.code === 'EACCES' || e?.code === 'EISDIR') {
      return printError(new Cdt3dError('io', 'Cannot open the file.', { file: opts.input }), opts.json);
    }
    return printError(e, opts.json);
  }
}

process.exitCode = await main(process.argv.slice(2));

