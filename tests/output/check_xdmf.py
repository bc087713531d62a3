"""Open a run's run.xdmf with ParaView (pvpython) and check what it reads.

Usage: pvpython check_xdmf.py RUN_DIR CONFIG_KIND
  taylor-green: the fluid velocity must be the analytic Taylor-Green field at
  every snapshot time, on the grid the configuration describes.
"""
import math
import sys

from paraview import servermanager
from paraview.simple import XDMFReader
from paraview.vtk.util.numpy_support import vtk_to_numpy

run_dir, kind = sys.argv[1], sys.argv[2]
reader = XDMFReader(FileNames=[run_dir + "/run.xdmf"])
reader.UpdatePipelineInformation()
times = list(reader.TimestepValues)
assert len(times) == 9, f"expected 9 snapshot times, ParaView sees {times}"

L, nx, U, nu = 0.1, 32, 0.01, 1.0e-4
k = 2 * math.pi / L
worst = 0.0
for t in times:
    reader.UpdatePipeline(t)
    data = servermanager.Fetch(reader)
    block = data.GetBlock(0) if data.IsA("vtkMultiBlockDataSet") else data
    while block.IsA("vtkMultiBlockDataSet"):
        block = block.GetBlock(0)
    assert block.GetNumberOfCells() == nx * nx, block.GetNumberOfCells()
    u = vtk_to_numpy(block.GetCellData().GetArray("velocity"))
    assert u.shape == (nx * nx, 3), u.shape
    p = block.GetCellData().GetArray("pressure")
    assert p is not None, "pressure missing"
    decay = math.exp(-2 * nu * k * k * t)
    for c in range(0, nx * nx, 37):
        i, j = c % nx, c // nx
        x, y = (i + 0.5) * L / nx, (j + 0.5) * L / nx
        ux = U * math.sin(k * x) * math.cos(k * y) * decay
        uy = -U * math.cos(k * x) * math.sin(k * y) * decay
        worst = max(worst, abs(u[c, 0] - ux), abs(u[c, 1] - uy))
assert worst < 1e-12, f"velocity differs from the analytic field by {worst}"
print(f"pvpython read {len(times)} snapshots; max |u - u_exact| = {worst:.2e}")
