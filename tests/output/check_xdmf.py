"""Open a run's run.xdmf with ParaView (pvpython) and check what it reads.

Usage: pvpython check_xdmf.py RUN_DIR
The run is configs/cases/taylor_green_vortex.yaml: a Taylor-Green vortex (amplitude U0, box L,
viscosity nu). ParaView must see every snapshot time, the 64 x 64 cell grid, the
velocity and pressure arrays, and a velocity within 1 % of U0 of the analytic
decaying vortex u = U0 (sin kx cos ky, -cos kx sin ky) exp(-2 nu k^2 t).
"""
import math
import sys

from paraview import servermanager
from paraview.simple import XDMFReader
from paraview.vtk.util.numpy_support import vtk_to_numpy

run_dir = sys.argv[1]
reader = XDMFReader(FileNames=[run_dir + "/run.xdmf"])
reader.UpdatePipelineInformation()
times = list(reader.TimestepValues)
expected_times = [5.0 * i for i in range(9)]
assert len(times) == len(expected_times) and all(abs(a - b) < 1e-9 for a, b in zip(times, expected_times)), times

L, n, U, nu = 0.064, 64, 2.0e-4, 1.0e-6
k = 2 * math.pi / L
worst = 0.0
for t in times:
    reader.UpdatePipeline(t)
    data = servermanager.Fetch(reader)
    block = data
    while block.IsA("vtkMultiBlockDataSet"):
        block = block.GetBlock(0)
    assert block.GetNumberOfCells() == n * n, block.GetNumberOfCells()
    u = vtk_to_numpy(block.GetCellData().GetArray("velocity"))
    assert u.shape == (n * n, 3), u.shape
    assert block.GetCellData().GetArray("pressure") is not None, "pressure missing"
    decay = math.exp(-2 * nu * k * k * t)
    for c in range(n * n):
        i, j = c % n, c // n
        x, y = (i + 0.5) * L / n, (j + 0.5) * L / n
        ux = U * math.sin(k * x) * math.cos(k * y) * decay
        uy = -U * math.cos(k * x) * math.sin(k * y) * decay
        for d in (abs(u[c, 0] - ux), abs(u[c, 1] - uy)):
            worst = math.inf if math.isnan(d) else max(worst, d)  # max() would drop a NaN
assert worst < 0.01 * U, f"velocity differs from the analytic vortex by {worst / U:.3%} of U0"
print(f"pvpython read {len(times)} snapshots of {n}x{n} cells; max |u - u_exact| = {worst / U:.3%} of U0")
