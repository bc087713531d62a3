"""Open a coupled run's run.xdmf with ParaView (pvpython) and check what it reads.

Usage: pvpython check_coupled_xdmf.py RUN_DIR
The run is configs/quickstart.yaml: five 8 mm balls settling through a fluid
(LBM <-> psm <-> DEM). ParaView must see every snapshot, the fluid grid with
velocity, pressure and solid_fraction, and the five particles with their radius.
The solid fraction summed over the grid must give the balls' volume (within
1e-3), and at the end the balls rest on the floor (centres one radius up).
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
expected = [0.1 * i for i in range(9)]
assert len(times) == len(expected) and all(abs(a - b) < 1e-9 for a, b in zip(times, expected)), times


def leaves(block):
    if block.IsA("vtkMultiBlockDataSet"):
        for i in range(block.GetNumberOfBlocks()):
            yield from leaves(block.GetBlock(i))
    elif block is not None:
        yield block


n_cells, dx, radius, balls = 32 * 32 * 64, 1.0e-3, 4.0e-3, 5
volume = balls * 4.0 / 3.0 * math.pi * radius ** 3
for t in times:
    reader.UpdatePipeline(t)
    fluid = particles = None
    for leaf in leaves(servermanager.Fetch(reader)):
        if leaf.GetCellData().GetArray("solid_fraction") is not None:
            fluid = leaf
        if leaf.GetPointData().GetArray("radius") is not None:
            particles = leaf
    assert fluid is not None, f"t={t}: no fluid grid with solid_fraction"
    assert particles is not None, f"t={t}: no particles with radius"
    assert fluid.GetNumberOfCells() == n_cells, fluid.GetNumberOfCells()
    for name in ("velocity", "pressure"):
        assert fluid.GetCellData().GetArray(name) is not None, name + " missing"
    solid = vtk_to_numpy(fluid.GetCellData().GetArray("solid_fraction")).sum() * dx ** 3
    assert abs(solid / volume - 1) < 7e-4, f"t={t}: solid volume {solid} vs {volume}"
    assert particles.GetNumberOfPoints() == balls, particles.GetNumberOfPoints()
    r = vtk_to_numpy(particles.GetPointData().GetArray("radius"))
    assert all(abs(x - radius) < 1e-12 for x in r), r
z = vtk_to_numpy(particles.GetPoints().GetData())[:, 2]
assert all(abs(zc - radius) < 0.05 * radius for zc in z), f"the balls do not rest on the floor: z = {z}"
print(f"pvpython read {len(times)} snapshots: fluid grid of {n_cells} cells and {balls} particles; "
      f"solid volume within {abs(solid / volume - 1):.1e}; balls on the floor")
