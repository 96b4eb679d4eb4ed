"""tools/replay_throughput.py on short recordings: the table it prints, and
its refusals. STRIDEMAP_TOOL names the stridemap program under test."""
import os
import subprocess
import sys

import pytest

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "tools", "replay_throughput.py")
TOOL = os.environ.get("STRIDEMAP_TOOL", "")


def run(*arguments):
    return subprocess.run([sys.executable, SCRIPT, *arguments], capture_output=True, text=True)


@pytest.mark.skipif(not TOOL, reason="STRIDEMAP_TOOL not set (ctest sets it)")
def test_log_replay_gives_both_lengths_and_a_rate(tmp_path):
    result = run("--tool", TOOL, "--scans", "100,600", "--bag", "off", "--work", str(tmp_path))
    assert result.returncode == 0, result.stderr
    rows = [line.split("|")[1:-1] for line in result.stdout.splitlines() if line.startswith("| map --log")]
    assert [int(row[1]) for row in rows] == [100, 600]
    for row in rows:
        assert float(row[2]) > 0 and float(row[3]) > 1.0  # CPU seconds, peak MB
    assert rows[0][4].strip() == ""
    rate = rows[1][4].strip()
    assert rate == "nan" or float(rate) > 0
    assert (tmp_path / "log_out_600" / "summary.json").is_file()


def test_a_missing_tool_is_named():
    result = run("--tool", "/no/such/stridemap", "--bag", "off")
    assert result.returncode == 1
    assert "--tool /no/such/stridemap: not an executable file" in result.stderr


@pytest.mark.parametrize("lengths", ["20000", "5,3", "0,10", "a,b"])
def test_bad_lengths_are_refused(lengths):
    result = run("--tool", TOOL or "/bin/true", "--scans", lengths)
    assert result.returncode == 1
    assert "--scans %s:" % lengths in result.stderr


@pytest.mark.skipif(not TOOL, reason="STRIDEMAP_TOOL not set (ctest sets it)")
def test_a_recording_already_in_the_work_folder_is_kept(tmp_path):
    kept = tmp_path / "r100.log"
    kept.write_text("a user's log\n")
    result = run("--tool", TOOL, "--scans", "100,600", "--bag", "off", "--work", str(tmp_path))
    assert result.returncode == 1
    assert "writing a recording failed" in result.stderr
    assert kept.read_text() == "a user's log\n"


def test_the_bag_writer_keeps_a_file_already_there(tmp_path):
    pytest.importorskip("rosbag")
    kept = tmp_path / "r.bag"
    kept.write_bytes(b"a user's bag")
    script = os.path.join(os.path.dirname(SCRIPT), "make_scan_bag.py")
    result = subprocess.run([sys.executable, script, "--scans", "3", "--bag", str(kept)], capture_output=True, text=True)
    assert result.returncode == 2
    assert "already exists" in result.stderr
    assert kept.read_bytes() == b"a user's bag"
