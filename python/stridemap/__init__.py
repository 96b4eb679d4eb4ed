"""stridemap: terrain elevation maps for walking robots (docs/python.md).

The mapping pipeline fed from NumPy, the map's layers as NumPy arrays, the
map file (.smap), the URG-04LX simulator and the paper's experiments. Every
name comes from the compiled extension ``stridemap._stridemap``; the stub
``__init__.pyi`` beside this file lists them with their types.
"""
from ._stridemap import (  # noqa: F401  (the public API)
    GridSizeError,
    InputError,
    Map,
    MapFile,
    Pipeline,
    PipelineOptions,
    Scene,
    SensorMount,
    UpdateOptions,
    UrgParameters,
    __version__,
    export_formats,
    is_map_file,
    load_map,
    load_scene,
    parse_scene,
    run_cart_rail,
    run_rocky_walk,
    scan_filters,
    simulate_urg_scans,
    simulate_walk,
    write_png,
)

__all__ = [
    "GridSizeError",
    "InputError",
    "Map",
    "MapFile",
    "Pipeline",
    "PipelineOptions",
    "Scene",
    "SensorMount",
    "UpdateOptions",
    "UrgParameters",
    "export_formats",
    "is_map_file",
    "load_map",
    "load_scene",
    "parse_scene",
    "run_cart_rail",
    "run_rocky_walk",
    "scan_filters",
    "simulate_urg_scans",
    "simulate_walk",
    "write_png",
]

# Tracebacks say stridemap.InputError, the name users import.
for _exported in (GridSizeError, InputError, Map, MapFile, Pipeline, PipelineOptions, Scene, SensorMount,
                  UpdateOptions, UrgParameters):
    _exported.__module__ = __name__
del _exported
