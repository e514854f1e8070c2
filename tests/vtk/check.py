"""Reads trubal's VTK files with the VTK library itself and checks them against the JSON
output of the same state (tests/it/vtk.rs runs it with the Python of .ci/vtk-venv).

    python check.py DIR PREFIX
    python check.py --arrays DIR PREFIX NAME,NAME,... [--contacts NAME,NAME,...] [--single]

The second form checks a frame of `VTk ARRays` (`CONtacts`, `SINgle`): each frame of the
series holds exactly the particle arrays named, in that order (and the contact arrays named
with --contacts, all without), and the last one's points and arrays are the JSON's (`PRint
Balls`, and `PRint Contacts` and `Grid` when the run printed them, of its state, the last in
out.jsonl); with --single the points are single precision, compared with the JSON's
positions rounded to single precision (exactly).

DIR holds out.jsonl (the run's --json output: `PRint Balls` of the reference state first
when the run took one, then `PRint Balls Contacts Walls Grid Clusters` of the state of the
last frame) and the frames in DIR/out. Single-precision arrays are compared with the JSON
value rounded to single precision (exactly); the points are double precision (exactly).
Exits non-zero with a message at the first difference.
"""

import json
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

KINDS = ["particles", "contacts", "walls", "cell"]
CONTACT_ARRAYS = ["a", "b", "wall", "force", "normal_force_vector", "tangential_force_vector",
                  "normal_force", "tangential_force", "overlap", "contact_radius",
                  "bridge_volume", "bridge"]


def fail(msg):
    print("VTK check failed: " + msg)
    sys.exit(1)


def same(what, got, want, f32=True):
    want = np.asarray(want, dtype=np.float64)
    if f32:
        want = want.astype(np.float32)
    got = np.asarray(got)
    if got.shape != want.shape:
        fail(f"{what}: shape {got.shape}, JSON {want.shape}")
    ok = (got == want) | (np.isnan(got) & np.isnan(want))
    if not ok.all():
        k = np.argwhere(~ok)[0]
        fail(f"{what}: at {tuple(k)} VTK {got[tuple(k)]!r}, JSON {want[tuple(k)]!r}")


def read(path):
    if not os.path.exists(path):
        fail(f"missing file {path}")
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0:
        fail(f"{path}: the VTK reader reports error {r.GetErrorCode()}")
    return r.GetOutput()


def arrays(data):
    return {data.GetArrayName(k): vtk_to_numpy(data.GetArray(k))
            for k in range(data.GetNumberOfArrays())}


def series(out, prefix):
    """Every kind's .pvd: its files exist, read, and carry the frame's time; returns the
    cycles of the frames (the same for every kind)."""
    cycles = None
    for kind in KINDS:
        root = ET.parse(os.path.join(out, f"{prefix}_{kind}.pvd")).getroot()
        sets = root.find("Collection").findall("DataSet")
        if not sets:
            fail(f"{kind}.pvd lists no frame")
        times = [float(s.get("timestep")) for s in sets]
        if times != sorted(times):
            fail(f"{kind}.pvd: times not in order: {times}")
        cs = []
        for s in sets:
            d = read(os.path.join(out, s.get("file")))
            fd = arrays(d.GetFieldData())
            if abs(fd["TimeValue"][0] - float(s.get("timestep"))) > 1e-12 * max(1.0, abs(fd["TimeValue"][0])):
                fail(f"{s.get('file')}: TimeValue {fd['TimeValue'][0]} but the .pvd says {s.get('timestep')}")
            cs.append(int(fd["cycle"][0]))
        if cycles is not None and cs != cycles:
            fail(f"{kind}.pvd frames {cs}, particles.pvd {cycles}")
        cycles = cs
    return cycles


def check_particles(d, balls, ref, contacts, clusters):
    n = len(balls)
    if d.GetNumberOfPoints() != n or d.GetNumberOfVerts() != n:
        fail(f"particles: {d.GetNumberOfPoints()} points, {d.GetNumberOfVerts()} vertices, JSON {n} balls")
    pts = vtk_to_numpy(d.GetPoints().GetData())
    same("particle positions", pts, [b["pos"] for b in balls], f32=False)
    a = arrays(d.GetPointData())
    same("id", a["id"], [b["id"] for b in balls], f32=False)
    for name, key in [("radius", "radius"), ("velocity", "vel"), ("spin", "spin"), ("force", "force")]:
        same(name, a[name], [b[key] for b in balls])
    same("material", a["material"], [b["material"] for b in balls], f32=False)
    same("size_type", a["size_type"], [b["size"] for b in balls], f32=False)
    same("agglomerate", a["agglomerate"], [b["agglomerate"] for b in balls], f32=False)
    # Coordination: solid contacts between particles, from PRint Contacts.
    z = {b["id"]: 0 for b in balls}
    for c in contacts:
        if "b" in c and c["touching"]:
            z[c["a"]] += 1
            z[c["b"]] += 1
    same("coordination", a["coordination"], [z[b["id"]] for b in balls], f32=False)
    # Clusters: the sizes of the groups of equal labels are PRint CLUsters' sizes.
    _, counts = np.unique(a["cluster"], return_counts=True)
    if sorted(counts.tolist(), reverse=True) != clusters["sizes"]:
        fail(f"cluster sizes {sorted(counts.tolist(), reverse=True)}, JSON {clusters['sizes']}")
    if ref is not None:
        at = {b["id"]: b["pos"] for b in ref}
        want = [np.subtract(b["pos"], at[b["id"]]) if b["id"] in at else [np.nan] * 3 for b in balls]
        same("displacement", a["displacement"], want)
    elif "displacement" in a:
        fail("displacement written without a reference state")


def check_contacts(d, balls, contacts, cell, names=CONTACT_ARRAYS, single=False):
    """The contacts file: a line per kept contact, from A's centre (the JSON's position,
    rounded to single precision with `single`) to B's nearest image or the wall, and the
    cell arrays `names` (exactly those, in that order) as the JSON's."""
    kept = [c for c in contacts if c["touching"] or "bridge" in c]
    if d.GetNumberOfLines() != len(kept):
        fail(f"contacts: {d.GetNumberOfLines()} lines, JSON {len(kept)} contacts")
    a = arrays(d.GetCellData())
    got = [d.GetCellData().GetArrayName(k) for k in range(d.GetCellData().GetNumberOfArrays())]
    if got != list(names):
        fail(f"contacts: cell arrays {got}, wanted {list(names)}")
    want = {
        "a": ([c["a"] for c in kept], False),
        "b": ([c.get("b", -1) for c in kept], False),
        "wall": ([c.get("wall", 0) for c in kept], False),
        "bridge": ([1 if "bridge" in c else 0 for c in kept], False),
        "bridge_volume": ([c["bridge"]["volume"] if "bridge" in c else 0 for c in kept], True),
    }
    for name in ["normal_force", "tangential_force", "overlap", "contact_radius"]:
        want[name] = ([c[name] for c in kept], True)
    for name, (values, f32) in want.items():
        if name in a:
            same(name, a[name], values, f32=f32)
    # Each line runs from A's centre to B's nearest image (or to the wall).
    pos = {b["id"]: np.array(b["pos"]) for b in balls}
    pts = vtk_to_numpy(d.GetPoints().GetData())
    if single and pts.dtype != np.float32 or not single and pts.dtype != np.float64:
        fail(f"contacts: points of type {pts.dtype}, single precision {single}")
    lines = d.GetLines()
    ids = vtk.vtkIdList()
    lines.InitTraversal()
    size = np.array(cell["size"])
    per = np.array(cell["periodic"])
    tol = (4e-7 if single else 1e-12) * size.max()
    for c in kept:
        lines.GetNextCell(ids)
        p0, p1 = pts[ids.GetId(0)], pts[ids.GetId(1)]
        at = pos[c["a"]].astype(np.float32) if single else pos[c["a"]]
        if not (p0 == at).all():
            fail(f"contact {c['a']}-{c.get('b')}: line starts at {p0}, A is at {pos[c['a']]}")
        length = np.linalg.norm(p1 - p0)
        if "b" in c:
            l = pos[c["b"]] - pos[c["a"]]
            l = np.where(per, l - size * np.round(l / size), l)
            if np.abs(p1 - p0 - l).max() > tol:
                fail(f"contact {c['a']}-{c['b']}: line {p1 - p0}, branch {l}")
        if length > 2.5 * max(b["radius"] for b in balls):
            fail(f"contact {c['a']}-{c.get('b')}: line {length} m long")
    for name in ["force", "normal_force_vector", "tangential_force_vector"]:
        if name in a and a[name].shape != (len(kept), 3):
            fail(f"{name}: shape {a[name].shape}")
    # The normal part of the force is along the line; normal + tangential = whole.
    if all(n in a for n in ["force", "normal_force_vector", "tangential_force_vector"]) and not np.allclose(
            a["normal_force_vector"] + a["tangential_force_vector"], a["force"], rtol=1e-5,
            atol=1e-6 * np.abs(a["force"]).max(initial=1e-30)):
        fail("normal + tangential force vectors are not the force")


def check_walls(d, walls):
    a = arrays(d.GetCellData())
    got = sorted(set(a["wall"].tolist())) if len(walls) else []
    if got != [w["wall"] for w in walls]:
        fail(f"walls in the file {got}, JSON {[w['wall'] for w in walls]}")
    pts = vtk_to_numpy(d.GetPoints().GetData())
    polys = d.GetPolys()
    ids = vtk.vtkIdList()
    polys.InitTraversal()
    for k in range(d.GetNumberOfPolys()):
        polys.GetNextCell(ids)
        w = walls[a["wall"][k] - 1]
        same(f"wall {w['wall']} force", a["force"][k], w["force"])
        same(f"wall {w['wall']} normal_force", a["normal_force"][k], w["normal_force"])
        g = w["geometry"]
        (kind, p), = g.items()
        for m in range(ids.GetNumberOfIds()):
            x = pts[ids.GetId(m)]
            if kind == "Plane":
                n = np.array(p["normal"])
                err = abs(n @ x - p["d"]) / np.linalg.norm(n)
            elif kind in ("Sphere", "Obstacle"):
                err = abs(np.linalg.norm(x - p["centre"]) - p["radius"])
            else:
                ax = np.array(p["axis"]) / np.linalg.norm(p["axis"])
                r = x - p["point"]
                err = abs(np.linalg.norm(r - (r @ ax) * ax) - p["radius"])
            if err > 1e-9:
                fail(f"wall {w['wall']} ({kind}): a vertex is {err} m off its surface")


def check_cell(d, grid):
    if d.GetNumberOfPoints() != 8 or d.GetNumberOfLines() != 12:
        fail("cell: not 8 corners and 12 edges")
    b = d.GetBounds()
    same("cell bounds", [b[1], b[3], b[5]], grid["size"], f32=False)
    same("cell origin", [b[0], b[2], b[4]], [0, 0, 0], f32=False)
    fd = arrays(d.GetFieldData())
    same("cell size", fd["size"].ravel(), grid["size"], f32=False)
    # The Lees–Edwards offset as PRint Grid prints it, in [−L_x/2, L_x/2).
    same("cell offset", fd["offset"].ravel(), [grid["offset"]], f32=False)


def check_field(path, fl):
    """The .vti of FIEld: its grid and every array, in double precision, as the JSON."""
    r = vtk.vtkXMLImageDataReader()
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0:
        fail(f"{path}: the VTK reader reports error {r.GetErrorCode()}")
    d = r.GetOutput()
    same("field nodes", d.GetDimensions(), fl["nodes"], f32=False)
    same("field spacing", d.GetSpacing(), fl["spacing"], f32=False)
    same("field origin", d.GetOrigin(), fl["origin"], f32=False)
    a = arrays(d.GetPointData())
    for name in ["density", "velocity", "stress_contact", "stress_kinetic", "solid_fraction", "coordination"]:
        same(f"field {name}", a[name], fl[name], f32=False)
    same("field stress", a["stress"], np.add(fl["stress_contact"], fl["stress_kinetic"]), f32=False)


def check_selection(top, prefix, names, contact_names, single):
    out = os.path.join(top, "out")
    rows = [json.loads(l) for l in open(os.path.join(top, "out.jsonl")) if l.startswith("{")]
    state = [r for r in rows if r.get("print") == "balls"][-1]
    balls = state["balls"]
    root = ET.parse(os.path.join(out, f"{prefix}_particles.pvd")).getroot()
    files = [s.get("file") for s in root.find("Collection").findall("DataSet")]
    for f in files:
        d = read(os.path.join(out, f))
        got = [d.GetPointData().GetArrayName(k) for k in range(d.GetPointData().GetNumberOfArrays())]
        if got != names:
            fail(f"{f}: point arrays {got}, wanted {names}")
        dc = read(os.path.join(out, f.replace("_particles_", "_contacts_")))
        got = [dc.GetCellData().GetArrayName(k) for k in range(dc.GetCellData().GetNumberOfArrays())]
        if got != contact_names:
            fail(f"{f}: contact arrays {got}, wanted {contact_names}")
    d = read(os.path.join(out, files[-1]))
    if int(arrays(d.GetFieldData())["cycle"][0]) != state["cycle"]:
        fail(f"the last frame is not of the JSON state's cycle {state['cycle']}")
    pts = vtk_to_numpy(d.GetPoints().GetData())
    if pts.dtype != (np.float32 if single else np.float64):
        fail(f"particles: points of type {pts.dtype}, single precision {single}")
    same("particle positions", pts, [b["pos"] for b in balls], f32=single)
    a = arrays(d.GetPointData())
    keys = {"radius": "radius", "velocity": "vel", "spin": "spin", "force": "force"}
    for name in names:
        if name == "id":
            same("id", a["id"], [b["id"] for b in balls], f32=False)
        elif name in keys:
            same(name, a[name], [b[keys[name]] for b in balls])
    contacts = [r for r in rows if r.get("print") == "contacts"]
    grid = [r for r in rows if r.get("print") == "grid"]
    if contacts and grid:
        if contacts[-1]["cycle"] != state["cycle"]:
            fail("the JSON contacts are not of the state of the balls")
        dc = read(os.path.join(out, files[-1].replace("_particles_", "_contacts_")))
        check_contacts(dc, balls, contacts[-1]["contacts"], grid[-1], contact_names, single)
    print(f"VTK check passed: {len(files)} frames with the arrays {names} and {contact_names}, "
          f"{len(balls)} particles, single {single}")


def main():
    if sys.argv[1] == "--arrays":
        rest = sys.argv[5:]
        contact_names = CONTACT_ARRAYS
        if "--contacts" in rest:
            contact_names = rest[rest.index("--contacts") + 1].split(",")
        check_selection(sys.argv[2], sys.argv[3], sys.argv[4].split(","), contact_names,
                        "--single" in rest)
        return
    top, prefix = sys.argv[1], sys.argv[2]
    out = os.path.join(top, "out")
    rows = [json.loads(l) for l in open(os.path.join(top, "out.jsonl")) if l.startswith("{")]
    by = lambda kind: [r for r in rows if r.get("print") == kind]
    balls = by("balls")
    state = balls[-1]
    ref = balls[0]["balls"] if len(balls) > 1 else None
    cycles = series(out, prefix)
    last = cycles[-1]
    if state["cycle"] != last:
        fail(f"the JSON state is of cycle {state['cycle']}, the last frame of cycle {last}")
    name = lambda kind: os.path.join(out, f"{prefix}_{kind}_c{last:08}.vtp")
    contacts = by("contacts")[-1]["contacts"]
    grid = by("grid")[-1]
    check_particles(read(name("particles")), state["balls"], ref, contacts, by("clusters")[-1])
    check_contacts(read(name("contacts")), state["balls"], contacts, grid)
    check_walls(read(name("walls")), by("walls")[-1]["walls"])
    check_cell(read(name("cell")), grid)
    fields = by("field")
    if fields:
        check_field(os.path.join(out, f"{prefix}_field_c{last:08}.vti"), fields[-1])
    print(f"VTK check passed: {len(cycles)} frames of {len(KINDS)} kinds, {len(state['balls'])} particles, {len(contacts)} contacts")


main()
