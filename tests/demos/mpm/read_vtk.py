"""Reads a shatter-mpm run back as ParaView would: mpm.pvd lists every frame's particles and
cracks .vtp, and Python's vtk (Debian's python3-vtk9) reads each one; their numbers must be
those of the same frame's CSV files (same 9 significant digits), and the index must list the
frames in time order.

    python3 read_vtk.py RUN_DIR

Prints "SKIPPED: ..." and exits 0 when vtk cannot be imported.
"""
import csv
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

try:
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: F401  (numpy is a vtk dependency)
except ImportError as e:
    print(f"SKIPPED: python3-vtk9 is not installed ({e})")
    sys.exit(0)


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def close(a, b):
    return math.isclose(a, b, rel_tol=1e-8, abs_tol=1e-12)


def read(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    if reader.GetErrorCode() != 0:
        fail(f"{path}: vtk cannot read it")
    return reader.GetOutput()


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


run = Path(sys.argv[1])
index = ET.parse(run / "mpm.pvd").getroot()
if index.get("type") != "Collection":
    fail("mpm.pvd is not a VTK collection")
datasets = index.find("Collection").findall("DataSet")
times = [float(d.get("timestep")) for d in datasets if d.get("part") == "0"]
if len(times) < 2 or times != sorted(times) or len(datasets) != 2 * len(times):
    fail(f"mpm.pvd lists {len(datasets)} datasets at times {times}")

checked = 0
for d in datasets:
    path = run / d.get("file")
    data = read(path)
    csv_path = path.with_suffix(".csv")
    table = rows(csv_path)
    points = data.GetPoints()
    if d.get("part") == "0":
        if data.GetNumberOfPoints() != len(table) or data.GetNumberOfVerts() != len(table):
            fail(f"{path}: {data.GetNumberOfPoints()} points, {len(table)} particles in {csv_path.name}")
        velocity = data.GetPointData().GetArray("velocity")
        stress = data.GetPointData().GetArray("stress")
        body = data.GetPointData().GetArray("body")
        for i, row in enumerate(table):
            x, y, z = points.GetPoint(i)
            vx, vy, _ = velocity.GetTuple3(i)
            s = stress.GetTuple9(i)
            expected = [float(row[k]) for k in ("x", "y", "vx", "vy", "sxx", "sxy", "syy")]
            got = [x, y, vx, vy, s[0], s[1], s[4]]
            if not all(close(a, b) for a, b in zip(got, expected)) or z != 0 or int(body.GetTuple1(i)) != int(row["body"]):
                fail(f"{path}: particle {i} is {got}, {csv_path.name} says {expected}")
    else:
        if data.GetNumberOfPoints() != len(table):
            fail(f"{path}: {data.GetNumberOfPoints()} crack points, {len(table)} in {csv_path.name}")
        cracks = {int(r["crack"]) for r in table}
        if data.GetNumberOfLines() != len(cracks):
            fail(f"{path}: {data.GetNumberOfLines()} polylines for {len(cracks)} cracks")
        for i, row in enumerate(table):
            x, y, _ = points.GetPoint(i)
            if not (close(x, float(row["x"])) and close(y, float(row["y"]))):
                fail(f"{path}: crack point {i} is ({x}, {y}), {csv_path.name} says ({row['x']}, {row['y']})")
    checked += 1
print(f"read {checked} .vtp files of {len(times)} frames back with vtk: they match the CSV files")
