"""Real floor plans in: ROS occupancy maps (YAML + PGM/PNG), DXF drawings and SVG drawings → environments.

:func:`import_floorplan` reads any of them into a validated :class:`~solverplan.environment.Environment`
in world coordinates (metres for maps) and says what it dropped on the way and where (speckle, spurs, other
components, faces and lines of a drawing), for a point robot or a disc of a given radius, with keepout areas. The pieces: :mod:`~solverplan.floorplan.occupancy` (maps),
:mod:`~solverplan.floorplan.vector` (DXF, SVG), :mod:`~solverplan.floorplan.outline` (simplify, snap, round).
"""

from solverplan.floorplan.drawing import DroppedFeature, free_space_from_linework
from solverplan.floorplan.importer import FloorplanImport, ImportResult, PlanFormat, import_floorplan
from solverplan.floorplan.occupancy import OccupancyMap, read_keepout_mask, read_occupancy_map, trace_free_space
from solverplan.floorplan.outline import environment_from_polygon, finish_outline, grid_quantum, snap_rectilinear
from solverplan.floorplan.robot import erode_free_space
from solverplan.floorplan.vector import arrange_rings, read_dxf_linework, read_dxf_rings, read_svg_rings

__all__ = [
    "DroppedFeature",
    "free_space_from_linework",
    "ImportResult",
    "read_keepout_mask",
    "environment_from_polygon",
    "erode_free_space",
    "read_dxf_linework",
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
