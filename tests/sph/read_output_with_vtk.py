#!/usr/bin/python3
"""Runs `unisph run` on a short dam break and reads its output back with VTK's own reader
(Debian's python3-vtk9): the .pvd lists every snapshot, each .vtp has the point count of
run.log, the expected arrays, ids 0..n-1 once each, densities near rho0 and finite values.

    read_output_with_vtk.py UNISPH_EXECUTABLE CASE_FILE WORK_DIR
"""
import math
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import vtk
from vtk.util.numpy_support import vtk_to_numpy


def main():
    exe, case, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    subprocess.run([exe, "run", case, "--policy", "seq", "--end-time", "0.5", "--output", work, "--quiet"], check=True)
    log = dict(line.split(": ", 1) for line in open(os.path.join(work, "run.log")).read().splitlines() if ": " in line)
    counts = {0: int(log["fluid particles"]), 1: int(log["wall particles"])}
    pvd = [f for f in os.listdir(work) if f.endswith(".pvd")]
    assert len(pvd) == 1, pvd
    entries = ET.parse(os.path.join(work, pvd[0])).getroot().find("Collection").findall("DataSet")
    assert len(entries) == 2 * int(log["snapshots"]), (len(entries), log["snapshots"])
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
        else:
            assert names == ["Normal"], names
            n = vtk_to_numpy(pd.GetArray("Normal"))
            assert all(abs(math.sqrt(a * a + b * b + c * c) - 1) < 1e-6 for a, b, c in n)
    print("read %d snapshots of %d fluid and %d wall particles back with VTK %s" %
          (len(entries) // 2, counts[0], counts[1], vtk.vtkVersion.GetVTKVersion()))


if __name__ == "__main__":
    main()
