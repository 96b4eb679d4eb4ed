"""tools/time-compiles.sh as a compiler launcher: the command's result and
output pass through unchanged, one line per command lands in the log, and
--summary adds the CPU up per build folder."""
import os
import subprocess

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "tools", "time-compiles.sh")


def launch(log, cwd, *command):
    env = dict(os.environ, STRIDEMAP_COMPILE_LOG=str(log))
    return subprocess.run(["bash", SCRIPT, *command], cwd=cwd, env=env, capture_output=True, text=True)


def test_a_command_runs_as_it_would_and_is_logged(tmp_path):
    build = tmp_path / "build-x" / "src"
    build.mkdir(parents=True)
    log = tmp_path / "compiles.log"
    ok = launch(log, build, "sh", "-c", "echo out; echo err >&2", "-o", "a.o")
    assert ok.returncode == 0 and ok.stdout == "out\n" and ok.stderr == "err\n"
    failed = launch(log, build, "sh", "-c", "exit 3")
    assert failed.returncode == 3
    lines = log.read_text().splitlines()
    assert len(lines) == 2
    user, system, wall, folder, output = lines[0].split()
    assert float(user) >= 0 and float(system) >= 0 and float(wall) >= 0
    assert folder == str(build) and output == "a.o"
    assert lines[1].split()[4] == "?"


def test_the_summary_adds_up_per_build_folder(tmp_path):
    log = tmp_path / "compiles.log"
    log.write_text("1.5 0.5 3.0 /builds/c/build/src x.o\n2.0 0.0 2.0 /c/build-tsan/tests y.o\n1.0 1.0 2.0 /c/build/tests z.o\n")
    result = subprocess.run(["bash", SCRIPT, "--summary", str(log)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    totals = {line.split()[2]: float(line.split()[0]) for line in result.stdout.splitlines()}
    assert totals == {"build": 4.0, "build-tsan": 2.0, "all": 6.0}


def test_a_missing_log_setting_is_a_clear_error(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "STRIDEMAP_COMPILE_LOG"}
    result = subprocess.run(["bash", SCRIPT, "true"], env=env, capture_output=True, text=True)
    assert result.returncode != 0 and "STRIDEMAP_COMPILE_LOG" in result.stderr
    missing = subprocess.run(["bash", SCRIPT, "--summary", str(tmp_path / "none.log")], capture_output=True, text=True)
    assert missing.returncode == 2 and "none.log" in missing.stderr
