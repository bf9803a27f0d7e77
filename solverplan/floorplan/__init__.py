"""Real floor plans in: ROS occupancy maps (YAML + PGM/PNG), DXF drawings and SVG drawings → environments.

:func:`import_floorplan` reads any of them into a validated :class:`~solverplan.environment.Environment`
in world coordinates (metres for maps) and says what it dropped on the way (speckle, spurs, other
components, simplified vertices). The pieces: :mod:`~solverplan.floorplan.occupancy` (maps),
:mod:`~solverplan.floorplan.vector` (DXF, SVG), :mod:`~solverplan.floorplan.outline` (simplify, snap, round).
"""

from solverplan.floorplan.importer import FloorplanImport, PlanFormat, import_floorplan
from solverplan.floorplan.occupancy import OccupancyMap, read_occupancy_map, trace_free_space
from solverplan.floorplan.outline import finish_outline, grid_quantum, snap_rectilinear
from solverplan.floorplan.vector import arrange_rings, read_dxf_rings, read_svg_rings

__all__ = [
    "FloorplanImport",
    "PlanFormat",
    "import_floorplan",
    "OccupancyMap",
    "read_occupancy_map",
    "trace_free_space",
    "finish_outline",
    "grid_quantum",
    "snap_rectilinear",
    "arrange_rings",
    "read_dxf_rings",
    "read_svg_rings",
]
