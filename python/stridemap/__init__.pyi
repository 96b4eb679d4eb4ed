# Type stub of the stridemap package (hand-written; python/tests checks that
# it names exactly the module's public attributes). docs/python.md.
from typing import Any, Optional, Sequence, Union

import os

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
PathLike = Union[str, "os.PathLike[str]"]
PoseLike = Union[Sequence[float], npt.NDArray[np.floating[Any]]]

class InputError(ValueError): ...
class GridSizeError(InputError): ...

class SensorMount:
    height_m: float
    pitch_rad: float
    forward_offset_m: float
    lateral_offset_m: float
    roll_rad: float
    yaw_rad: float
    def __init__(
        self,
        height_m: float = ...,
        pitch_rad: float = ...,
        forward_offset_m: float = ...,
        lateral_offset_m: float = ...,
        roll_rad: float = ...,
        yaw_rad: float = ...,
    ) -> None: ...

class UrgParameters:
    first_step: int
    last_step: int
    front_step: int
    steps_per_turn: int
    min_range_m: float
    max_range_m: float
    scan_period_s: float
    @property
    def beam_count(self) -> int: ...
    def __init__(
        self,
        *,
        first_step: int = ...,
        last_step: int = ...,
        front_step: int = ...,
        steps_per_turn: int = ...,
        min_range_m: float = ...,
        max_range_m: float = ...,
        scan_period_s: float = ...,
    ) -> None: ...
    def validate(self) -> None: ...

class UpdateOptions:
    certainty_increment: float
    certainty_max: float
    max_pitch_error_rad: float
    max_roll_error_rad: float
    max_mount_pitch_error_rad: float
    use_turning_term: bool
    elevation_rule: str
    replace_after_contradictions: int
    def __init__(
        self,
        *,
        certainty_increment: float = ...,
        certainty_max: float = ...,
        max_pitch_error_rad: float = ...,
        max_roll_error_rad: float = ...,
        max_mount_pitch_error_rad: float = ...,
        use_turning_term: bool = ...,
        elevation_rule: str = ...,
        replace_after_contradictions: int = ...,
    ) -> None: ...

class PipelineOptions:
    sensor: str
    mount: SensorMount
    foothold_update_every_scan: bool
    urg: UrgParameters
    cells_per_side: int
    cell_size_m: float
    follow_robot: bool
    window_ahead_m: float
    reject_stale_scans: bool
    update: UpdateOptions
    filters: str
    map_filter: str
    sigma_scale: float
    def __init__(
        self,
        *,
        sensor: str = ...,
        mount: SensorMount = ...,
        foothold_update_every_scan: bool = ...,
        urg: UrgParameters = ...,
        cells_per_side: int = ...,
        cell_size_m: float = ...,
        follow_robot: bool = ...,
        window_ahead_m: float = ...,
        reject_stale_scans: bool = ...,
        update: UpdateOptions = ...,
        filters: str = ...,
        map_filter: str = ...,
        sigma_scale: float = ...,
    ) -> None: ...
    @staticmethod
    def from_config(path: PathLike, sensor: str = "urg") -> PipelineOptions: ...
    def load_structured_light_config(self, path: PathLike) -> None: ...

class Map:
    def __init__(self, cells_per_side: int = 100, cell_size_m: float = 0.01) -> None: ...
    def copy(self) -> Map: ...
    @property
    def cells_per_side(self) -> int: ...
    @property
    def cell_size_m(self) -> float: ...
    @property
    def min_cell(self) -> tuple[int, int]: ...
    @property
    def extent_m(self) -> tuple[float, float, float, float]: ...
    @property
    def storage_corner(self) -> tuple[int, int]: ...
    @property
    def layer_names(self) -> tuple[str, ...]: ...
    def cell_of(self, x_m: float, y_m: float) -> tuple[int, int]: ...
    def cell_center(self, ix: int, iy: int) -> tuple[float, float]: ...
    def cells_of(self, points_m: ArrayLike) -> np.ndarray: ...
    def centers_of(self, cells: ArrayLike) -> np.ndarray: ...
    def x_m(self) -> np.ndarray: ...
    def y_m(self) -> np.ndarray: ...
    def contains(self, ix: int, iy: int) -> bool: ...
    def layer(self, name: str) -> npt.NDArray[Any]: ...
    def storage_view(self, name: str) -> npt.NDArray[Any]: ...
    def layers(self) -> dict[str, npt.NDArray[Any]]: ...
    def __getitem__(self, name: str) -> npt.NDArray[Any]: ...
    def __contains__(self, name: object) -> bool: ...
    __iter__: None  # type: ignore[assignment]
    def submap(self, min_x_m: float, min_y_m: float, max_x_m: float, max_y_m: float) -> Map: ...
    @staticmethod
    def from_arrays(
        elevation_m: ArrayLike,
        certainty: ArrayLike,
        *,
        cell_size_m: float,
        corner_m: Optional[Sequence[float]] = None,
        state: Optional[ArrayLike] = None,
        layers: Optional[dict[str, ArrayLike]] = None,
    ) -> Map: ...
    def add_layer(
        self,
        name: str,
        dtype: str = "float32",
        reset_value: float = 0.0,
        unit: str = "",
        description: str = "",
    ) -> None: ...
    def save(
        self,
        path: PathLike,
        *,
        created_by: Optional[str] = None,
        config_text: Optional[str] = None,
        mount: Optional[SensorMount] = None,
        last_scan_time_s: Optional[float] = None,
        last_pose: Optional[dict[str, Optional[float]]] = None,
        overwrite_other_files: bool = False,
    ) -> None: ...
    def export_npy(self, directory: PathLike) -> list[str]: ...
    def export_ply(self, path: PathLike) -> dict[str, int]: ...
    def export_csv(self, directory: PathLike) -> str: ...
    def export(self, format: str, path: PathLike, layers: Sequence[str] = ...) -> list[str]: ...
    def write_pictures(self, directory: PathLike, *, title: str = "Elevation", certainty_max: float = 100.0) -> None: ...

class MapFile:
    @property
    def map(self) -> Map: ...
    @property
    def metadata(self) -> dict[str, Any]: ...
    @property
    def version(self) -> int: ...

class Pipeline:
    def __init__(
        self, options: PipelineOptions = ..., resume_from: Optional[Map] = None, *, fused_heights: bool = False
    ) -> None: ...
    def add_urg_scan(
        self,
        ranges: ArrayLike,
        time_s: float,
        pose: PoseLike,
        *,
        units: str = "mm",
        first_step: Optional[int] = None,
        cluster: int = 1,
        reference_elevation_m: float = 0.0,
        height_change_m: float = 0.0,
    ) -> dict[str, Any]: ...
    def add_urg_scans(
        self,
        ranges: ArrayLike,
        times_s: ArrayLike,
        poses: ArrayLike,
        *,
        units: str = "mm",
        reference_elevation_m: Optional[ArrayLike] = None,
        height_change_m: Optional[ArrayLike] = None,
    ) -> int: ...
    def add_points(
        self,
        points: ArrayLike,
        sigma_m: ArrayLike,
        time_s: float,
        pose: PoseLike,
        *,
        reference_elevation_m: float = 0.0,
        height_change_m: float = 0.0,
    ) -> dict[str, Any]: ...
    def add_stripe(
        self,
        pixels: ArrayLike,
        time_s: Optional[float],
        pose: PoseLike,
        *,
        reference_elevation_m: float = 0.0,
        height_change_m: float = 0.0,
    ) -> dict[str, Any]: ...
    def stance_height(
        self,
        feet: ArrayLike,
        *,
        sole_radius_m: float = 0.02,
        min_known_share: float = 0.5,
        gate_sigmas: float = 2.5,
        depth_sigma_m: float = 0.002,
    ) -> dict[str, Any]: ...
    def finish(self) -> dict[str, Any]: ...
    def apply_map_filter(self) -> dict[str, int]: ...
    def filtered_map(self) -> Map: ...
    def save(
        self, path: PathLike, *, created_by: str = "Python stridemap.Pipeline", overwrite_other_files: bool = False
    ) -> None: ...
    @property
    def map(self) -> Map: ...
    @property
    def options(self) -> PipelineOptions: ...
    @property
    def last_scan_time_s(self) -> Optional[float]: ...
    @property
    def stats(self) -> dict[str, int]: ...

class Scene:
    def surface_height_at(self, x_m: float, y_m: float) -> float: ...
    def max_height_in_rect(self, min_x_m: float, min_y_m: float, max_x_m: float, max_y_m: float) -> float: ...
    @property
    def has_walk_path(self) -> bool: ...
    @property
    def has_cart_rail(self) -> bool: ...
    @property
    def box_count(self) -> int: ...
    @property
    def cylinder_count(self) -> int: ...

def scan_filters() -> list[dict[str, Any]]: ...
def export_formats() -> list[dict[str, Any]]: ...
def load_map(path: PathLike) -> MapFile: ...
def is_map_file(path: PathLike) -> bool: ...
def write_png(path: PathLike, pixels: ArrayLike) -> None: ...
def load_scene(path: PathLike) -> Scene: ...
def parse_scene(text: str, source_name: str = "<scene>") -> Scene: ...
def simulate_urg_scans(
    scene: Scene,
    poses: ArrayLike,
    times_s: ArrayLike,
    *,
    mount: SensorMount = ...,
    urg: UrgParameters = ...,
    seed: int = 1,
    noise: bool = True,
    systematic_error: bool = True,
    dropouts: bool = True,
) -> npt.NDArray[np.uint32]: ...
def simulate_walk(
    scene: Scene,
    *,
    mount: SensorMount = ...,
    urg: UrgParameters = ...,
    seed: int = 1,
    duration_s: Optional[float] = None,
    noise: bool = True,
    systematic_error: bool = True,
    dropouts: bool = True,
) -> dict[str, npt.NDArray[Any]]: ...
def run_rocky_walk(
    scene_path: PathLike,
    *,
    seed: int = 1,
    sweep: Sequence[float] = ...,
    reference: str = "map-footholds",
    calibrate_attitude: bool = True,
    calibrate_range: bool = False,
    mixed_pixels: bool = False,
    coupling: bool = True,
    filters: str = "",
    map_filter: str = "fill",
    pose_error_scale: float = 1.0,
    out_dir: Optional[str] = None,
) -> dict[str, Any]: ...
def run_cart_rail(
    scene_path: PathLike,
    *,
    sensor: str = "urg",
    seed: int = 1,
    cell_size_m: Optional[float] = None,
    cells_per_side: int = 0,
    mixed_pixels: bool = False,
    coupling: bool = True,
    filters: str = "",
    map_filter: Optional[str] = None,
    elevation_rule: str = "paper",
    pipeline: str = "image",
    out_dir: Optional[str] = None,
) -> dict[str, Any]: ...
