"""Open fv's adaptive-grid snapshots with ParaView (pvpython) and check what it reads.

Usage: pvpython check_amr_xdmf.py DIR
DIR holds composite_2d.xmf (2 levels) and composite_3d.xmf (3 levels) written by
the unit test "amr output" (tests/unit/fluid/test_amr_output.cpp): every level
must come as a block of quadrilaterals (hexahedra) with the arrays "value" and
"level", the value being 1 + x + 10 y + 100 z at each cell's centre.
"""
import math
import sys

from paraview import servermanager
from paraview.simple import XDMFReader
from paraview.vtk.util.numpy_support import vtk_to_numpy

run_dir = sys.argv[1]
for dims, levels, expected_cells in ((2, 2, 112), (3, 3, 5888)):
    reader = XDMFReader(FileNames=[f"{run_dir}/composite_{dims}d.xmf"])
    reader.UpdatePipeline()
    data = servermanager.Fetch(reader)
    assert data.IsA("vtkMultiBlockDataSet"), data.GetClassName()
    corners = 8 if dims == 3 else 4
    cells, seen_levels, worst = 0, set(), 0.0
    for b in range(data.GetNumberOfBlocks()):
        block = data.GetBlock(b)
        n = block.GetNumberOfCells()
        cells += n
        points = vtk_to_numpy(block.GetPoints().GetData()).reshape(n, corners, 3)
        centres = points.mean(axis=1)
        value = vtk_to_numpy(block.GetCellData().GetArray("value"))
        level = vtk_to_numpy(block.GetCellData().GetArray("level"))
        seen_levels.update(int(v) for v in set(level.ravel()))
        exact = 1 + centres[:, 0] + 10 * centres[:, 1] + 100 * centres[:, 2]
        err = float(abs(value.ravel() - exact).max())
        worst = math.inf if math.isnan(err) else max(worst, err)  # max() would drop a NaN
    assert cells == expected_cells, (dims, cells)
    assert seen_levels == set(range(levels)), seen_levels
    assert worst < 1e-12, worst
    print(f"pvpython read {dims}D: {data.GetNumberOfBlocks()} level blocks, {cells} cells, value error {worst:.1e}")
