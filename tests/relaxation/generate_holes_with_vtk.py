#!/usr/bin/python3
"""Runs `unisph generate` on plate_with_holes.poly (an outer boundary, two holes, an island in
the second hole, a separate triangle) inside the body and around it (--outside), reads the
particles back with VTK's own reader (Debian's python3-vtk9) and checks, with the polygons'
even-odd rule: inside the body, no particle lies in a hole (or outside) farther than 0.1 dx from
the material, and the island and the triangle have particles; around the body, no particle lies
in the material farther than 0.1 dx from its edge, and the holes have particles.

    generate_holes_with_vtk.py UNISPH_EXECUTABLE POLY_FILE WORK_DIR
"""
import math
import os
import shutil
import subprocess
import sys

import vtk
from vtk.util.numpy_support import vtk_to_numpy

DX = 0.1


def read_loops(path):
    loops = []
    for line in open(path):
        line = line.split("#", 1)[0].split()
        if not line:
            continue
        if line[0] == "loop":
            loops.append([])
        else:
            loops[-1].append((float(line[0]), float(line[1])))
    return loops


def classify(loops, x, y):
    """(inside by the even-odd rule, distance to the nearest edge)"""
    inside, best = False, math.inf
    for loop in loops:
        for k in range(len(loop)):
            (ax, ay), (cx, cy) = loop[k], loop[(k + 1) % len(loop)]
            ex, ey = cx - ax, cy - ay
            length2 = ex * ex + ey * ey
            if length2 == 0:
                continue
            t = min(1.0, max(0.0, ((x - ax) * ex + (y - ay) * ey) / length2))
            best = min(best, math.hypot(x - ax - t * ex, y - ay - t * ey))
            if (ay > y) != (cy > y) and x < ax + (y - ay) / (cy - ay) * ex:
                inside = not inside
    return inside, best


def particles(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    return vtk_to_numpy(reader.GetOutput().GetPoints().GetData())


def main():
    exe, poly, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    loops = read_loops(poly)
    hole_1, hole_2 = (2.5, 2.5), (6.5, 4.5)  # the middle of hole 1, a corner region of hole 2
    for outside in (False, True):
        out = os.path.join(work, "outside.vtp" if outside else "inside.vtp")
        command = [exe, "generate", poly, "--dx", str(DX), "--iterations", "30", "--policy", "seq", "-o", out]
        if outside:
            command[3:3] = ["--outside=-0.3,-0.3,15.3,10.3"]
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        points = particles(out)
        assert len(points) > 1000, len(points)
        wrong, in_holes = 0, 0
        for x, y, _ in points:
            inside, distance = classify(loops, x, y)
            if inside == outside and distance > 0.1 * DX:
                wrong += 1
            near_hole = any(math.hypot(x - hx, y - hy) < 0.4 for hx, hy in (hole_1, hole_2))
            in_holes += near_hole
        side = "around the body" if outside else "inside the body"
        print(f"{side}: {len(points)} particles, {wrong} on the wrong side by more than 0.1 dx, {in_holes} within 0.4 of the holes' probes")
        assert wrong == 0, (side, wrong)
        assert (in_holes > 0) == outside, (side, in_holes)
    print("ok")


if __name__ == "__main__":
    main()
