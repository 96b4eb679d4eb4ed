"""An array the bindings must convert (another dtype, non-contiguous) whose
converted copy cannot be allocated is a MemoryError naming the argument,
never a crash.

Each case runs in a child interpreter whose address space is capped just
above what it already uses, so that the copy fails there and nowhere else;
the input is a broadcast array, gigabytes as NumPy sees it and a few bytes
in memory. A crash shows as the child's signal, not as a lost test run.
"""
import os
import subprocess
import sys
import textwrap

import pytest

import stridemap

PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(stridemap.__file__)))

# Room for the call's own small allocations (messages, Python objects); far
# below the copies, which need 2 GiB or more.
HEADROOM_BYTES = 256 << 20

CHILD = textwrap.dedent("""
    import resource, sys
    import numpy as np
    import stridemap

    HUGE = 1 << 28  # elements: a float64 copy of 2 GiB

    def huge(dtype, shape):
        # Every element the same zero: no memory of its own, and neither
        # contiguous nor (for float32 and integers) float64.
        return np.broadcast_to(np.zeros((), dtype), shape)

    scene = stridemap.parse_scene(
        "terrain: {kind: flat, extent: {min_x_m: 0, min_y_m: 0, max_x_m: 1, max_y_m: 1}, "
        "base_elevation_m: 0, reflectance: 0.5}", "flat.yaml")
    pipeline = stridemap.Pipeline()
    pose = [0.0, 0.0, 0.0, 0.0, 0.0]
    scan = np.full(682, 1000, np.uint16)
    CALLS = {
        "add_urg_scan ranges": lambda: pipeline.add_urg_scan(huge(np.int32, (HUGE,)), 1.0, pose),
        "add_urg_scan ranges m": lambda: pipeline.add_urg_scan(huge(np.float32, (HUGE,)), 1.0, pose, units="m"),
        "add_urg_scan pose": lambda: pipeline.add_urg_scan(scan, 1.0, huge(np.float32, (HUGE,))),
        "add_urg_scans ranges": lambda: pipeline.add_urg_scans(huge(np.uint16, (HUGE // 682 + 1, 682)), [1.0], [pose]),
        "add_urg_scans times_s": lambda: pipeline.add_urg_scans([scan], huge(np.float32, (HUGE,)), [pose]),
        "add_urg_scans poses": lambda: pipeline.add_urg_scans([scan], [1.0], huge(np.float32, (HUGE, 5))),
        "add_urg_scans reference_elevation_m": lambda: pipeline.add_urg_scans(
            [scan], [1.0], [pose], reference_elevation_m=huge(np.float32, (HUGE,))),
        "add_points points": lambda: pipeline.add_points(huge(np.float32, (HUGE, 3)), 0.01, 1.0, pose),
        "add_points sigma_m": lambda: pipeline.add_points(np.zeros((1, 3)), huge(np.float32, (HUGE,)), 1.0, pose),
        "add_stripe pixels": lambda: pipeline.add_stripe(huge(np.float32, (HUGE, 2)), 1.0, pose),
        "simulate_urg_scans poses": lambda: stridemap.simulate_urg_scans(scene, huge(np.float32, (HUGE, 5)), [0.0]),
        "simulate_urg_scans times_s": lambda: stridemap.simulate_urg_scans(scene, [pose], huge(np.float32, (HUGE,))),
        "write_png pixels": lambda: stridemap.write_png(sys.argv[2], huge(np.uint8, (1 << 15, 1 << 15, 3))),
    }
    call = CALLS[sys.argv[1]]

    with open("/proc/self/statm") as f:
        in_use = int(f.read().split()[0]) * resource.getpagesize()
    resource.setrlimit(resource.RLIMIT_AS, (in_use + int(sys.argv[3]), resource.getrlimit(resource.RLIMIT_AS)[1]))
    try:
        call()
        print("no error")
    except MemoryError as e:
        print("MemoryError:", e)
    except Exception as e:
        print(type(e).__name__ + ":", e)
""")

CASES = {
    "add_urg_scan ranges": "ranges",
    "add_urg_scan ranges m": "ranges",
    "add_urg_scan pose": "pose",
    "add_urg_scans ranges": "ranges",
    "add_urg_scans times_s": "times_s",
    "add_urg_scans poses": "poses",
    "add_urg_scans reference_elevation_m": "reference_elevation_m",
    "add_points points": "points",
    "add_points sigma_m": "sigma_m",
    "add_stripe pixels": "pixels",
    "simulate_urg_scans poses": "poses",
    "simulate_urg_scans times_s": "times_s",
    "write_png pixels": "pixels",
}


def run_child(case, tmp_path):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (PACKAGE_ROOT, env.get("PYTHONPATH")) if p)
    # One BLAS thread: its threads' stacks would count against the cap.
    env["OPENBLAS_NUM_THREADS"] = "1"
    return subprocess.run([sys.executable, "-c", CHILD, case, str(tmp_path / "big.png"), str(HEADROOM_BYTES)],
                          env=env, capture_output=True, text=True, timeout=120)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="caps the address space through /proc and RLIMIT_AS")
@pytest.mark.parametrize("case", sorted(CASES))
def test_a_copy_that_cannot_be_allocated_is_a_memory_error(case, tmp_path):
    child = run_child(case, tmp_path)
    assert child.returncode == 0, (
        f"{case}: the child ended with {child.returncode} (negative: killed by signal {-child.returncode}), "
        f"not with an exception\nstdout: {child.stdout}\nstderr: {child.stderr}")
    report = child.stdout.strip()
    assert report.startswith("MemoryError:"), f"{case}: {report}\nstderr: {child.stderr}"
    assert CASES[case] + ":" in report, f"{case}: the message does not name the argument: {report}"
    assert not (tmp_path / "big.png").exists()


def test_no_binding_converts_with_array_t_ensure():
    # ensure() returns a null array when the copy fails (the crash above);
    # every conversion goes through numpy_input.cpp's helpers instead.
    source = os.path.join(os.path.dirname(__file__), "..", "src")
    for folder, _, names in os.walk(source):
        for name in sorted(names):
            path = os.path.join(folder, name)
            with open(path, encoding="utf-8") as f:
                code = [line for line in f if not line.lstrip().startswith("//")]
            where = os.path.relpath(path, os.path.join(source, ".."))
            assert not any("::ensure(" in line for line in code), f"python/{where} calls array_t::ensure"
