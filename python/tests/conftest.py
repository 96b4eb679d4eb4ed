"""Shared fixtures: a flat-floor scene with a walk path, simulated once."""
import os

import numpy as np
import pytest

import stridemap

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# A flat floor 0.05 m above the map origin's plane, so that a map that
# ignored the scene (all zeros, or the sensor's own height) cannot pass.
FLOOR_M = 0.05
FLAT_WALK_SCENE = f"""
terrain:
  kind: flat
  extent: {{min_x_m: -0.5, min_y_m: -1.0, max_x_m: 2.5, max_y_m: 1.0}}
  base_elevation_m: {FLOOR_M}
  reflectance: 0.5
walk_path:
  start: {{x_m: 0.0, y_m: 0.0, yaw_deg: 0}}
  segments:
    - straight_m: 0.6
"""


@pytest.fixture(scope="session")
def flat_scene():
    return stridemap.parse_scene(FLAT_WALK_SCENE, "flat_walk.yaml")


@pytest.fixture(scope="session")
def flat_walk(flat_scene):
    return stridemap.simulate_walk(flat_scene, seed=7, duration_s=4.0)


def map_walk(walk, options=None):
    pipeline = stridemap.Pipeline(options or stridemap.PipelineOptions())
    pipeline.add_urg_scans(walk["ranges_mm"], walk["times_s"], walk["poses"],
                           reference_elevation_m=walk["reference_elevation_m"],
                           height_change_m=walk["height_change_m"])
    return pipeline


@pytest.fixture()
def mapped_flat_walk(flat_walk):
    return map_walk(flat_walk)


def known(values, state):
    return values[state == 1]
