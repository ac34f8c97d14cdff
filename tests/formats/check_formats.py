#!/usr/bin/env python3
"""Reads cdt3d's Gmsh and VTU output back with other people's readers.

usage: check_formats.py CDT3D_CLI MODEL WORKDIR

Meshes MODEL with `cdt3d mesh` five times: TetGen files (the reference: our
plainest writer, coordinates exact with %.17g) plus --format msh,
msh-binary, vtk and vtu. Then:
  - Gmsh (`gmsh FILE -check`) loads each .msh without a warning or error
    and counts the same nodes and elements; Gmsh's own VTK export of it,
    read by VTK, has the same tets and triangles, each in the physical group
    write_msh documents (entity tag = physical tag);
  - meshio reads the .msh files: the same points (bit for bit), tets with
    their region attribute and triangles with their facet marker, through
    the physical groups' names; tets have positive volume;
  - meshio and VTK's vtkXMLUnstructuredGridReader read the .vtu: the same
    points, tets in our order, region, min_dihedral and steiner_kind;
  - VTK's legacy reader reads the .vtk: the same counts, positive volumes.
Exit 77 (skipped) only when gmsh, meshio or VTK is missing
(tests/scripts/setup.sh installs them).
"""
import contextlib
import io
import json
import os
import re
import subprocess
import sys
from collections import Counter

SKIP = 77


def skip(why):
    print(f"SKIP: {why} (tests/scripts/setup.sh installs gmsh python3-meshio python3-vtk9)")
    sys.exit(SKIP)


try:
    import meshio
    import numpy as np
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError as e:
    skip(f"{e.name} is not installed for {sys.executable}")
GMSH = "/usr/bin/gmsh" if os.path.exists("/usr/bin/gmsh") else None
if GMSH is None:
    skip("gmsh is not installed")

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print(f"FAIL: {what}")


def run(args):
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        print(p.stdout, p.stderr)
        raise SystemExit(f"FAIL: {' '.join(args)} exited with {p.returncode}")
    return p.stdout + p.stderr


def table(path):
    """Rows of numbers of a TetGen file (comments and the header line dropped)."""
    rows = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].split()
            if line:
                rows.append(line)
    return rows[1:]


def reference(cli, model, prefix):
    stats = json.loads(run([cli, "mesh", model, "--json", "-o", prefix]))
    points = np.array([[float(x) for x in r[1:4]] for r in table(prefix + ".node")])
    ele = table(prefix + ".ele")
    tets = np.array([[int(x) for x in r[1:5]] for r in ele], dtype=np.int64).reshape(-1, 4)
    attrs = [float(r[5]) for r in ele] if ele and len(ele[0]) > 5 else None
    face = table(prefix + ".face")
    faces = np.array([[int(x) for x in r[1:4]] for r in face], dtype=np.int64).reshape(-1, 3)
    markers = [int(r[4]) for r in face] if face and len(face[0]) > 4 else None
    return stats, points, tets, attrs, faces, markers


def volume_tags(attrs, nt):
    """Physical tag per tet, by the rule cdt3d.hpp states for write_msh."""
    if attrs is None:
        return [1] * nt
    values = sorted(set(attrs))
    natural = all(a >= 1 and a == int(a) and a <= 2**31 - 1 for a in values)
    tag = {a: int(a) if natural else i + 1 for i, a in enumerate(values)}
    return [tag[a] for a in attrs]


def surface_tags(markers, nf):
    if markers is None:
        return [1] * nf
    values = sorted(set(markers))
    nxt = max(0, values[-1]) + 1
    tag = {}
    for m in values:
        if m > 0:
            tag[m] = m
        else:
            tag[m], nxt = nxt, nxt + 1
    return [tag[m] for m in markers]


def keyed(cells, labels):
    """Multiset of (sorted vertex ids, label): order and orientation free."""
    return Counter((tuple(sorted(int(v) for v in c)), lab) for c, lab in zip(cells, labels))


def signed_volumes(points, tets):
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)


def check_gmsh(path, np_, tets, faces, vtags, ftags):
    name = os.path.basename(path)
    out = run([GMSH, path, "-check"])
    bad = [l for l in out.splitlines() if re.match(r"\s*(Warning|Error)", l)]
    check(not bad, f"gmsh {name}: {bad[:3]}")
    nodes = re.search(r"Info\s*:\s*(\d+) nodes", out)
    elems = re.search(r"Info\s*:\s*(\d+) elements", out)
    check(nodes and int(nodes.group(1)) == np_, f"gmsh {name}: nodes {nodes and nodes.group(1)} != {np_}")
    check(elems and int(elems.group(1)) == len(tets) + len(faces),
          f"gmsh {name}: elements {elems and elems.group(1)} != {len(tets) + len(faces)}")
    # What Gmsh understood, written by Gmsh, read by VTK.
    exported = path + ".gmsh.vtk"
    out = run([GMSH, path, "-0", "-o", exported])
    bad = [l for l in out.splitlines() if re.match(r"\s*(Warning|Error)", l)]
    check(not bad, f"gmsh {name} -0: {bad[:3]}")
    r = vtk.vtkUnstructuredGridReader()
    r.SetFileName(exported)
    r.Update()
    g = r.GetOutput()
    check(g.GetNumberOfPoints() == np_, f"gmsh export of {name}: {g.GetNumberOfPoints()} points != {np_}")
    types = vtk_to_numpy(g.GetCellTypesArray()) if g.GetNumberOfCells() else np.zeros(0)
    conn = vtk_to_numpy(g.GetCells().GetConnectivityArray()) if g.GetNumberOfCells() else np.zeros(0)
    offs = vtk_to_numpy(g.GetCells().GetOffsetsArray()) if g.GetNumberOfCells() else np.zeros(1)
    ids = vtk_to_numpy(g.GetCellData().GetArray("CellEntityIds"))
    cells = [conn[offs[i]:offs[i + 1]] for i in range(len(types))]
    got_t = keyed([c for c, t in zip(cells, types) if t == 10], [int(i) for i, t in zip(ids, types) if t == 10])
    got_f = keyed([c for c, t in zip(cells, types) if t == 5], [int(i) for i, t in zip(ids, types) if t == 5])
    check(got_t == keyed(tets, vtags), f"gmsh export of {name}: tets or their volume tags differ")
    check(got_f == keyed(faces, ftags), f"gmsh export of {name}: triangles or their surface tags differ")
    os.remove(exported)


def read_quietly(path):
    """meshio.read without the empty line meshio 5's Gmsh reader prints."""
    with contextlib.redirect_stdout(io.StringIO()):
        return meshio.read(path)


def input_marker_names(model):
    """The names the input gives markers, by the rule cdt3d documents
    (Plc::marker_names), read here on our own: OBJ "g"/"o" lines name
    markers 1, 2, ... in order of first use; an ASCII STL's named solids
    name markers 0, 1, ... in order."""
    names = {}
    ext = os.path.splitext(model)[1].lower()
    with open(model, "rb") as f:
        data = f.read()
    if ext == ".obj":
        for line in data.decode("latin-1").splitlines():
            w = line.split("#")[0].split()
            if w and w[0] in ("g", "o") and len(w) > 1:
                name = " ".join(w[1:])[:200]
                if name not in names.values():
                    names[len(names) + 1] = name
    elif ext == ".stl" and data[:5].lower() == b"solid" and b"facet" in data[:1000].lower():
        solids, next_marker = 0, None
        for line in data.decode("latin-1").splitlines():
            w = line.split()
            if not w or w[0].lower() != "solid":
                continue
            solids += 1
            name = " ".join(w[1:])[:200]
            if name and name not in names.values():
                if next_marker is None:
                    next_marker = 0 if solids == 1 else 1
                names[next_marker] = name
                next_marker += 1
    return names


def check_meshio_msh(path, points, tets, attrs, faces, markers, names):
    name = os.path.basename(path)
    m = read_quietly(path)
    check(np.array_equal(m.points, points), f"meshio {name}: points differ")
    by_dim = {}
    for n, (tag, dim) in m.field_data.items():
        by_dim[(int(dim), int(tag))] = n
    got_t, got_f = [], []
    for block, phys in zip(m.cells, m.cell_data["gmsh:physical"]):
        for c, t in zip(block.data, phys):
            if block.type == "tetra":
                got_t.append((c, by_dim[(3, int(t))]))
            elif block.type == "triangle":
                got_f.append((c, by_dim[(2, int(t))]))
            else:
                check(False, f"meshio {name}: unexpected cell type {block.type}")
    check(len(got_t) == len(tets), f"meshio {name}: {len(got_t)} tets != {len(tets)}")
    check(len(got_f) == len(faces), f"meshio {name}: {len(got_f)} triangles != {len(faces)}")
    # Labels through the group names: "region A" and "marker M" as in the input.
    t_labels = [float(n.split()[1]) if n.startswith("region ") else n for _, n in got_t]
    # Markers the input names come back under their names.
    by_name = {n: m for m, n in names.items()}
    f_labels = [by_name[n] if n in by_name else int(n.split()[1]) if n.startswith("marker ") else n
                for _, n in got_f]
    check(all(n in by_name or n.startswith("marker ") or n == "boundary" for _, n in got_f),
          f"meshio {name}: a surface group with a name the input does not give")
    want_t = attrs if attrs is not None else ["domain"] * len(tets)
    want_f = markers if markers is not None else ["boundary"] * len(faces)
    check(keyed([c for c, _ in got_t], t_labels) == keyed(tets, want_t),
          f"meshio {name}: tets or their regions differ")
    check(keyed([c for c, _ in got_f], f_labels) == keyed(faces, want_f),
          f"meshio {name}: triangles or their markers differ")
    if got_t:
        vol = signed_volumes(m.points, np.array([c for c, _ in got_t], dtype=np.int64))
        check(vol.min() > 0, f"meshio {name}: a tet with volume {vol.min()} <= 0")


def check_legacy_vtk(path, points, tets):
    """The legacy .vtk through VTK's own reader: the same points and tets,
    all with positive volume (right-handed, as VTK's tets are)."""
    name = os.path.basename(path)
    r = vtk.vtkUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    check(g.GetNumberOfPoints() == len(points) and g.GetNumberOfCells() == len(tets),
          f"VTK {name}: {g.GetNumberOfPoints()} points, {g.GetNumberOfCells()} cells")
    if len(tets):
        size = vtk.vtkCellSizeFilter()
        size.SetInputData(g)
        size.Update()
        vol = vtk_to_numpy(size.GetOutput().GetCellData().GetArray("Volume"))
        check(vol.min() > 0, f"VTK {name}: a tet with volume {vol.min()} <= 0")


def min_dihedral(points, tets):
    """Smallest dihedral angle per tet, degrees (independent numpy version)."""
    pairs = [(0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2), (1, 2, 0, 3), (1, 3, 0, 2), (2, 3, 0, 1)]
    angles = []
    for i, j, k, l in pairs:  # edge (i, j), faces (i, j, k) and (i, j, l)
        e = points[tets[:, j]] - points[tets[:, i]]
        u = points[tets[:, k]] - points[tets[:, i]]
        w = points[tets[:, l]] - points[tets[:, i]]
        e = e / np.linalg.norm(e, axis=1)[:, None]
        u = u - np.einsum("ij,ij->i", u, e)[:, None] * e
        w = w - np.einsum("ij,ij->i", w, e)[:, None] * e
        c = np.einsum("ij,ij->i", u, w) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1))
        angles.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
    return np.min(angles, axis=0)


def check_vtu(path, stats, points, tets, attrs):
    name = os.path.basename(path)
    right_handed = tets[:, [0, 2, 1, 3]]
    m = read_quietly(path)
    check(np.array_equal(m.points, points), f"meshio {name}: points differ")
    check([b.type for b in m.cells] == (["tetra"] if len(tets) else []), f"meshio {name}: cell blocks {[b.type for b in m.cells]}")
    if len(tets):
        check(np.array_equal(m.cells[0].data, right_handed), f"meshio {name}: tets differ")
    if attrs is not None:
        check(np.array_equal(m.cell_data["region"][0], np.array(attrs)), f"meshio {name}: region differs")
    else:
        check("region" not in m.cell_data, f"meshio {name}: region without attributes")
    dihedral = m.cell_data["min_dihedral"][0]
    # acos near 0 degrees is ill-conditioned (an error of sqrt(eps) rad, about
    # 1e-6 degrees, from rounding alone): compare to 1e-4 degrees.
    check(np.allclose(dihedral, min_dihedral(points, tets), rtol=0, atol=1e-4),
          f"meshio {name}: min_dihedral differs from a recomputation")
    if len(tets):
        check(abs(dihedral.min() - stats["minDihedral"]) < 1e-9,
              f"meshio {name}: smallest min_dihedral {dihedral.min()} != stats {stats['minDihedral']}")
    kinds = m.point_data["steiner_kind"]
    n_in = stats["inputPoints"]
    want = Counter({0: n_in, 1: stats["steinerSegment"], 2: stats["steinerFacet"], 3: stats["steinerVolume"]})
    got = Counter({k: int(v) for k, v in zip(*np.unique(kinds, return_counts=True))})
    check(+got == +want and not kinds[:n_in].any(), f"meshio {name}: steiner_kind counts {dict(got)} != {dict(want)}")

    errors = []
    r = vtk.vtkXMLUnstructuredGridReader()
    for event in ("ErrorEvent", "WarningEvent"):
        r.AddObserver(event, lambda obj, ev: errors.append(ev))
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    check(not errors, f"VTK {name}: {errors}")
    check(g.GetNumberOfPoints() == len(points) and g.GetNumberOfCells() == len(tets),
          f"VTK {name}: {g.GetNumberOfPoints()} points, {g.GetNumberOfCells()} cells")
    if len(points):
        check(np.array_equal(vtk_to_numpy(g.GetPoints().GetData()), points), f"VTK {name}: points differ")
    if len(tets):
        check(set(vtk_to_numpy(g.GetCellTypesArray()).tolist()) == {10}, f"VTK {name}: cell types")
        conn = vtk_to_numpy(g.GetCells().GetConnectivityArray()).reshape(-1, 4)
        check(np.array_equal(conn, right_handed), f"VTK {name}: tets differ")
        size = vtk.vtkCellSizeFilter()
        size.SetInputData(g)
        size.Update()
        vol = vtk_to_numpy(size.GetOutput().GetCellData().GetArray("Volume"))
        check(vol.min() > 0, f"VTK {name}: a tet with volume {vol.min()} <= 0")
    cd, pd = g.GetCellData(), g.GetPointData()
    for arr, want_arr in (("min_dihedral", dihedral), ("region", None if attrs is None else np.array(attrs))):
        a = cd.GetArray(arr)
        if want_arr is None:
            check(a is None, f"VTK {name}: {arr} without attributes")
        else:
            check(a is not None and np.array_equal(vtk_to_numpy(a), want_arr), f"VTK {name}: {arr} differs")
    a = pd.GetArray("steiner_kind")
    check(a is not None and np.array_equal(vtk_to_numpy(a), kinds), f"VTK {name}: steiner_kind differs")


def main():
    cli, model, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    prefix = os.path.join(work, os.path.basename(model))
    stats, points, tets, attrs, faces, markers = reference(cli, model, prefix)
    check(len(points) == stats["points"] and len(tets) == stats["tets"] and len(faces) == stats["faces"],
          "TetGen files disagree with the statistics")
    vtags, ftags = volume_tags(attrs, len(tets)), surface_tags(markers, len(faces))
    for fmt in ("msh", "msh-binary"):
        base = f"{prefix}.{fmt}"
        run([cli, "mesh", model, "-q", "-o", base, "--format", fmt])
        check_gmsh(base + ".msh", len(points), tets, faces, vtags, ftags)
        check_meshio_msh(base + ".msh", points, tets, attrs, faces, markers, input_marker_names(model))
    run([cli, "mesh", model, "-q", "-o", prefix, "--format", "vtk"])
    check_legacy_vtk(prefix + ".vtk", points, tets)
    run([cli, "mesh", model, "-q", "-o", prefix, "--format", "vtu"])
    check_vtu(prefix + ".vtu", stats, points, tets, attrs)
    regions = "none" if attrs is None else len(set(attrs))
    groups = "none" if markers is None else len(set(markers))
    print(f"{os.path.basename(model)}: {len(points)} points, {len(tets)} tets, {len(faces)} triangles, "
          f"regions {regions}, marker groups {groups}: gmsh, meshio, VTK "
          + ("agree" if not failures else f"{len(failures)} failures"))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
