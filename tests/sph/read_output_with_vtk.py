#!/usr/bin/python3
"""Runs `unisph run` on a short dam break and reads its output back with VTK's own reader
(Debian's python3-vtk9): the .pvd lists every snapshot, each .vtp has the point count of
run.log, the expected arrays, ids 0..n-1 once each, densities near rho0 and finite values.
With --obstacle x0,y0,x1,y1 (a case with one rectangular [[obstacle]] there): the wall also has
the array Body (0 the tank, 1 the obstacle) with run.log's count of obstacle particles, all of
them inside the rectangle and unmoved between snapshots, and no fluid particle of any snapshot
lies deeper inside the rectangle than a quarter of dx.

    read_output_with_vtk.py UNISPH_EXECUTABLE CASE_FILE WORK_DIR [--obstacle x0,y0,x1,y1] [--end-time T]
"""
import math
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import vtk
from vtk.util.numpy_support import vtk_to_numpy


def depth_inside(box, x, y):
    """How deep (x, y) lies inside the rectangle box = (x0, y0, x1, y1); <= 0 outside."""
    return min(x - box[0], box[2] - x, y - box[1], box[3] - y)


def main():
    exe, case, work = sys.argv[1:4]
    options = dict(zip(sys.argv[4::2], sys.argv[5::2]))
    box = [float(v) for v in options["--obstacle"].split(",")] if "--obstacle" in options else None
    shutil.rmtree(work, ignore_errors=True)
    subprocess.run([exe, "run", case, "--policy", "seq", "--end-time", options.get("--end-time", "0.5"), "--output", work,
                    "--quiet"], check=True)
    log = dict(line.split(": ", 1) for line in open(os.path.join(work, "run.log")).read().splitlines() if ": " in line)
    dx = float(log["dx"])
    deepest = -math.inf
    first_obstacle = None
    # The fluid is part 0; each wall body ("wall body NAME: N particles" in the log, in order) a part of its own.
    bodies = [(line.split(": ")[0][len("wall body "):], int(line.split(": ")[1].split()[0]))
              for line in open(os.path.join(work, "run.log")).read().splitlines() if line.startswith("wall body ")]
    assert sum(n for _, n in bodies) == int(log["wall particles"]), (bodies, log["wall particles"])
    counts = {0: int(log["fluid particles"])}
    for k, (_, n) in enumerate(bodies):
        counts[k + 1] = n
    pvd = [f for f in os.listdir(work) if f.endswith(".pvd")]
    assert len(pvd) == 1, pvd
    entries = ET.parse(os.path.join(work, pvd[0])).getroot().find("Collection").findall("DataSet")
    assert len(entries) == (1 + len(bodies)) * int(log["snapshots"]), (len(entries), log["snapshots"])
    for e in entries:
        reader = vtk.vtkXMLPolyDataReader()
        reader.SetFileName(os.path.join(work, e.get("file")))
        reader.Update()
        data = reader.GetOutput()
        part = int(e.get("part"))
        assert data.GetNumberOfPoints() == counts[part], (e.get("file"), data.GetNumberOfPoints(), counts[part])
        points = vtk_to_numpy(data.GetPoints().GetData())
        assert points.shape == (counts[part], 3) and (points == points).all()
        pd = data.GetPointData()
        names = sorted(pd.GetArrayName(k) for k in range(pd.GetNumberOfArrays()))
        if part == 0:
            assert names == ["Density", "ParticleId", "Pressure", "Velocity"], names
            ids = sorted(vtk_to_numpy(pd.GetArray("ParticleId")).tolist())
            assert ids == list(range(counts[0])), "ids are not 0..n-1"
            rho = vtk_to_numpy(pd.GetArray("Density"))
            assert abs(rho.mean() - 1.0) < 0.02 and rho.min() > 0.9 and rho.max() < 1.1, (rho.min(), rho.max())
            v = vtk_to_numpy(pd.GetArray("Velocity"))
            assert v.shape == (counts[0], 3) and abs(v[:, 2]).max() == 0.0
            t = float(e.get("timestep"))
            assert (t == 0.0) == (abs(v).max() == 0.0), "velocity zero exactly at t = 0"
            if box:
                deepest = max(deepest, max(depth_inside(box, x, y) for x, y, _ in points))
        else:
            assert names == ["Normal", "ParticleId"], names
            assert e.get("file").startswith(bodies[part - 1][0] + "_"), (e.get("file"), bodies[part - 1])
            n = vtk_to_numpy(pd.GetArray("Normal"))
            assert all(abs(math.sqrt(a * a + b * b + c * c) - 1) < 1e-6 for a, b, c in n)
            if box and bodies[part - 1][0] == "obstacle_1":
                obstacle = points
                expected = int(log["obstacle 1"].split()[0])
                assert len(obstacle) == expected, (len(obstacle), expected)
                assert all(depth_inside(box, x, y) > 0 for x, y, _ in obstacle), "an obstacle particle outside its block"
                if first_obstacle is None:
                    first_obstacle = sorted(map(tuple, obstacle.tolist()))
                assert sorted(map(tuple, obstacle.tolist())) == first_obstacle, "the obstacle moved"
    if box:
        assert deepest < 0.25 * dx, "a fluid particle %.3f dx inside the obstacle" % (deepest / dx)
        print("obstacle: %d wall particles, unmoved in every snapshot; the deepest fluid particle is %.3f dx inside "
              "the block (bound 0.25 dx; < 0: none inside)" % (len(first_obstacle), deepest / dx))
    print("read %d snapshots of %d fluid and %d wall particles back with VTK %s" %
          (int(log["snapshots"]), counts[0], int(log["wall particles"]), vtk.vtkVersion.GetVTKVersion()))


if __name__ == "__main__":
    main()
