#!/usr/bin/env node
// `npx cdt3d mesh MODEL [-o PREFIX] [--format node|vtk|vtu|mesh|msh|msh-binary] [--keep-hull]
//  [--validate] [--stats] [--json] [-q] [--quality [RATIO]] [--max-volume V]
//  [--min-dihedral D] [--max-points N]` and `npx cdt3d info MODEL [--json]`:
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
  mesh MODEL [-o PREFIX] [--format node|vtk|vtu|mesh|msh|msh-binary] [--keep-hull]
             [--validate] [--stats] [--json] [-q] [--merge] [--paper-degeneracy] [--no-intersection-check]
             [--stop-after PHASE] [--quality [RATIO]] [--max-volume V] [--min-dihedral D]
             [--max-points N] [--one-thread]
                           constrained Delaunay tetrahedralization of MODEL;
                           --quality (radius-edge bound RATIO >= 1, default 2.0),
                           --max-volume, --min-dihedral (0-70 degrees, by flips and
                           smoothing) and --max-points each turn quality refinement on;
                           --one-thread: the single-threaded module (same result)

MODEL: .stl (ASCII/binary) .off .obj .ply .poly .smesh
exit codes: 0 success, 1 input or meshing error, 2 usage error
`;

function usage(message) {
  if (message) process.stderr.write(`cdt3d: ${message}\n`);
  process.stderr.write(USAGE);
  return EXIT_USAGE;
}

// The quality options: CLI word -> field of the JS option `quality`.
const QUALITY_FLAGS = { '--quality': 'radiusEdge', '--max-volume': 'maxVolume', '--min-dihedral': 'minDihedral', '--max-points': 'maxPoints' };
const NUMBER = /^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/;

function parse(args) {
  const opts = { input: null, prefix: null, format: 'node', json: false, quiet: false, stats: false, threads: true, tet: {}, qualityFlags: [] };
  for (let i = 0; i < args.length; ++i) {
    const a = args[i];
    if (Object.hasOwn(QUALITY_FLAGS, a)) {
      const quality = (opts.tet.quality ??= {});
      const next = args[i + 1];
      opts.qualityFlags.push(a);
      // The ratio of --quality is optional: the next word only if it is a number.
      if (a === '--quality' && !(next !== undefined && NUMBER.test(next))) continue;
      if (next === undefined) return { error: `${a} needs a value` };
      const whole = a === '--max-points';
      if (!(whole ? /^\d+$/ : NUMBER).test(next)) return { error: `${a} takes ${whole ? 'a whole number >= 0' : 'a number'}, not '${next}'` };
      quality[QUALITY_FLAGS[a]] = Number(next);
      ++i;
    } else if (a === '--json') opts.json = true;
    else if (a === '-q') opts.quiet = true;
    else if (a === '--stats') opts.stats = true;
    else if (a === '--one-thread') opts.threads = false;
    else if (a === '--keep-hull') opts.tet.keepConvexHull = true;
    else if (a === '--validate') opts.tet.validate = true;
    else if (a === '--no-intersection-check') opts.tet.checkIntersections = false;
    else if (a === '--keep-triangles') opts.tet.keepTriangles = true;
    else if (a === '--merge') opts.tet.keepTriangles = false;  // the default, named
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
  if (!['node', 'vtk', 'vtu', 'mesh', 'msh', 'msh-binary'].includes(opts.format)) return { error: `unknown format '${opts.format}'` };
  if (opts.tet.stopAfter !== undefined && !['delaunay', 'segments', 'degeneracy', 'facets'].includes(opts.tet.stopAfter)) {
    return { error: `--stop-after takes delaunay, segments, degeneracy or facets, not '${opts.tet.stopAfter}'` };
  }
  if (opts.tet.quality && opts.tet.stopAfter !== undefined) {
    return { error: `${opts.qualityFlags[0]} refines the finished CDT; it cannot go with --stop-after` };
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

const RATIO_BINS = ['<1', '1-1.5', '1.5-2', '2-3', '3-5', '5-10', '10-20', '20-50', '50-100', '>100'];
const ANGLE_BINS = ['<1', '1-5', '5-10', '10-15', '15-20', '20-30', '30-40', '40-50', '50-60', '>60'];

// One histogram line of --stats, as the native CLI prints it.
function histogram(title, bins, counts) {
  return `  ${title.padEnd(26)}${bins.map((b, i) => ` ${b}: ${counts[i]}`).join('')}`;
}

function table(file, s, validated, refined, stats) {
  const lines = [
    file,
    `  Input points:              ${s.inputPoints}`,
    `  Input facets:              ${s.inputFacets}`,
    `  Input segments:            ${s.inputSegments}`,
    `  Mesh points:               ${s.points}`,
    `  Mesh tetrahedra:           ${s.tets}`,
    `  Mesh constrained faces:    ${s.faces}`,
    `  Steiner points:            ${s.steinerSegment + s.steinerFacet + s.steinerVolume} (segments ${s.steinerSegment}, facets ${s.steinerFacet} of which ${s.facetSplits} in failed facet regions, volume ${s.steinerVolume})`,
  ];
  if (refined) {
    lines.push(
      `  Quality refinement:        ${s.refineSegment + s.refineFacet + s.refineVolume} points (segments ${s.refineSegment}, facets ${s.refineFacet}, volume ${s.refineVolume}); ${s.refineSkipped} bad tets left where no split point fits (${s.refineSmallAngle} at small input angles)${s.refineCapped ? '; stopped at the point limit (--max-points)' : ''}`,
      `  Sliver improvement:        ${s.improveFlips} flips, ${s.improveSmooths} vertex moves, ${s.improvePoints} points added`,
    );
  }
  lines.push(
    `  Flat tetrahedra:           ${s.flatTets} in the output, ${s.flatFlips} removed by flips${s.flatPeeled > 0 ? `, ${s.flatPeeled} left out of the hull` : ''}`,
    `  Time (ms):                 read ${s.msRead.toFixed(1)}, delaunay ${s.msDelaunay.toFixed(1)}, segments ${s.msSegments.toFixed(1)}, degeneracy ${s.msDegeneracy.toFixed(1)}, facets ${s.msFacets.toFixed(1)}, carve ${s.msCarve.toFixed(1)}, ${refined ? `refine ${s.msRefine.toFixed(1)}, ` : ''}total ${s.msTotal.toFixed(1)}`,
  );
  if (stats && refined) {
    lines.push(
      `  Dihedral angles (deg):     min ${s.minDihedral.toFixed(3)} (before refinement ${s.minDihedralBefore.toFixed(3)}), max ${s.maxDihedral.toFixed(3)}`,
      histogram('Radius-edge ratios before:', RATIO_BINS, s.radiusEdgeHistogramBefore),
      histogram('Radius-edge ratios after:', RATIO_BINS, s.radiusEdgeHistogram),
      histogram('Min dihedral/tet before:', ANGLE_BINS, s.dihedralHistogramBefore),
      histogram('Min dihedral/tet after:', ANGLE_BINS, s.dihedralHistogram),
    );
  } else if (stats) {
    lines.push(
      `  Dihedral angles (deg):     min ${s.minDihedral.toFixed(3)}, max ${s.maxDihedral.toFixed(3)}`,
      histogram('Radius-edge ratios:', RATIO_BINS, s.radiusEdgeHistogram),
      histogram('Min dihedral/tet (deg):', ANGLE_BINS, s.dihedralHistogram),
    );
  }
  if (validated) lines.push('  Validation:                passed');
  return `${lines.join('\n')}\n`;
}

// A bad quality value is a usage error, as in the native CLI, naming the
// CLI word instead of the JS field; null for any other error.
function qualityUsage(e) {
  const m = e instanceof Cdt3dError && e.code === 'invalid-argument' && /^tetrahedralize: option "?quality\.(\w+)"?:? (.*)$/s.exec(e.message);
  if (!m) return null;
  const flag = Object.keys(QUALITY_FLAGS).find((k) => QUALITY_FLAGS[k] === m[1]) ?? `quality.${m[1]}`;
  process.stderr.write(`cdt3d mesh: ${flag}: ${m[2]}\n`);
  return EXIT_USAGE;
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
  const cdt = await createCdt3d({ threads: opts.threads });
  try {
    const bytes = readFileSync(opts.input);
    if (command === 'info') {
      const info = cdt.readPlc(bytes, opts.input);
      process.stdout.write(opts.json ? `${JSON.stringify({ ok: true, ...info })}\n` : `${Object.entries(info).map(([k, v]) => `${k}: ${v}`).join('\n')}\n`);
      return EXIT_OK;
    }
    const r = cdt.tetrahedralize({ bytes, fileName: opts.input }, opts.tet);
    if (opts.prefix !== null) {
      const formats = opts.format === 'node' ? (opts.tet.stopAfter ? ['node', 'ele'] : ['node', 'ele', 'face']) : [opts.format];
      // msh-binary is a .msh file too (Gmsh tells the two apart by their header).
      for (const f of formats) writeFileSync(`${opts.prefix}.${f === 'msh-binary' ? 'msh' : f}`, cdt.write(r, f));
    }
    if (opts.json) process.stdout.write(`${JSON.stringify({ ok: true, phase: opts.tet.stopAfter ?? 'done', ...r.stats, valid: opts.tet.validate ? true : null })}\n`);
    else if (!opts.quiet) process.stdout.write(table(opts.input, r.stats, opts.tet.validate, !!opts.tet.quality, opts.stats));
    return EXIT_OK;
  } catch (e) {
    const usageExit = qualityUsage(e);
    if (usageExit !== null) return usageExit;
    if (e?.code === 'ENOENT' || e?.code === 'EACCES' || e?.code === 'EISDIR') {
      return printError(new Cdt3dError('io', 'Cannot open the file.', { file: opts.input }), opts.json);
    }
    return printError(e, opts.json);
  }
}

process.exitCode = await main(process.argv.slice(2));

