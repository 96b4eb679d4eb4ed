#!/usr/bin/env python3
"""Maps a simulated walk over the rocky mock-up and plots it.

The robot walks the scene's walk_path; the URG-04LX simulator gives the raw
scans it would see; the mapping pipeline builds the local map from them and
the true poses. The map is plotted with matplotlib when it is installed,
otherwise drawn with NumPy and written by the library's own PNG writer.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/map_walk.py --out out/python-walk

Writes OUT/map.png (the elevation, the path on top; replaced if it exists),
OUT/walk.smap (the map file) and, from the library, OUT/pictures/ with
elevation.png and certainty.png with legends. docs/python.md walks through it.
"""
import argparse
import os
import sys

import numpy as np

import stridemap

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCENE = os.path.join(HERE, "..", "..", "scenes", "rocky_mockup.yaml")


def map_walk(scene_path, seed, duration_s):
    scene = stridemap.load_scene(scene_path)
    walk = stridemap.simulate_walk(scene, seed=seed, duration_s=duration_s)
    options = stridemap.PipelineOptions()
    # A 3 x 3 m window instead of the paper's 1 x 1 m local map: it still
    # follows the robot, but holds the whole 2 x 2 m mock-up from anywhere
    # on the walk, so the picture shows everything the robot saw.
    options.cells_per_side = 300
    options.cell_size_m = 0.01
    pipeline = stridemap.Pipeline(options)
    pipeline.add_urg_scans(walk["ranges_mm"], walk["times_s"], walk["poses"],
                           reference_elevation_m=walk["reference_elevation_m"],
                           height_change_m=walk["height_change_m"])
    pipeline.apply_map_filter()
    return pipeline, walk


def colours(values, lo, hi):
    """A blue-to-yellow ramp; unknown cells grey."""
    t = np.clip((values - lo) / max(hi - lo, 1e-9), 0.0, 1.0)
    rgb = np.stack([t * 253 + (1 - t) * 68, t * 231 + (1 - t) * 1, t * 37 + (1 - t) * 84], axis=-1)
    rgb[np.isnan(values)] = 160
    return rgb.astype(np.uint8)


def plot_with_numpy(m, walk, path, scale=2):
    # Rows of the map run along +X (forward), columns along +Y (left): the
    # picture shows +X up and +Y to the left, as the library's pictures do.
    elevation = m.layer("elevation")
    known = elevation[~np.isnan(elevation)]
    lo, hi = (float(known.min()), float(known.max())) if known.size else (0.0, 1.0)
    image = colours(elevation, lo, hi)[::-1, ::-1]
    n = m.cells_per_side
    for x, y in walk["poses"][:, :2]:
        ix, iy = m.cell_of(x, y)
        i, j = ix - m.min_cell[0], iy - m.min_cell[1]
        if 0 <= i < n and 0 <= j < n:
            image[n - 1 - i, n - 1 - j] = (230, 30, 30)
    image = np.repeat(np.repeat(image, scale, axis=0), scale, axis=1)
    stridemap.write_png(path, np.ascontiguousarray(image))


def plot_with_matplotlib(plt, m, walk, path):
    x0, y0, x1, y1 = m.extent_m
    fig, ax = plt.subplots(figsize=(6, 6))
    shown = ax.imshow(m.layer("elevation").T, origin="lower", extent=(x0, x1, y0, y1), cmap="viridis")
    ax.plot(walk["poses"][:, 0], walk["poses"][:, 1], "r-", linewidth=1, label="trunk path")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend()
    fig.colorbar(shown, label="elevation [m]")
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default=DEFAULT_SCENE, help="scene file with a walk_path (YAML)")
    parser.add_argument("--out", required=True, help="output folder (created if missing)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the simulation")
    parser.add_argument("--duration-s", type=float, default=None, help="walk only this long [s]")
    args = parser.parse_args(argv)

    pipeline, walk = map_walk(args.scene, args.seed, args.duration_s)
    m = pipeline.map
    os.makedirs(args.out, exist_ok=True)
    state = m.layer("state")
    print(f"{walk['times_s'].size} scans, {np.count_nonzero(state == 1)} cells measured, "
          f"{np.count_nonzero(state == 2)} filled")
    m.save(os.path.join(args.out, "walk.smap"), created_by="examples/python/map_walk.py")
    m.write_pictures(os.path.join(args.out, "pictures"), title="Simulated walk")
    picture = os.path.join(args.out, "map.png")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: drawing the map with NumPy and stridemap.write_png")
        plot_with_numpy(m, walk, picture)
    else:
        plot_with_matplotlib(plt, m, walk, picture)
    print(f"wrote {picture}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
