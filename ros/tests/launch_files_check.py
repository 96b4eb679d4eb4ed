"""The launch files as roslaunch reads them: each parses with its default
arguments, and every node in it (includes followed) is an executable that
roslaunch finds in the build's package folder (ROS_PACKAGE_PATH set by the
test), and answers --help. Usage: launch_files_check.py PACKAGE_PARENT_DIR LAUNCH_FILE...
Run with Debian's python3 (roslaunch is a Debian Python module)."""
import os
import subprocess
import sys


def does_not_start(executable):
    """An executable roslaunch finds must also load its libraries: each
    program answers --help without a master. The emulator's wrapper script
    is left out: it starts the emulator."""
    if executable.endswith(".sh"):
        return []
    try:
        done = subprocess.run([executable, "--help"], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired) as e:
        return [f"{executable} --help: {e}"]
    if done.returncode != 0:
        return [f"{executable} --help: exit {done.returncode}: {done.stderr.strip()[:300]}"]
    return []


def main():
    os.environ["ROS_PACKAGE_PATH"] = sys.argv[1]
    import rospkg
    import roslaunch.config
    import roslib.packages

    rospack = rospkg.RosPack()
    failures = []
    for path in sys.argv[2:]:
        name = os.path.basename(path)
        try:
            config = roslaunch.config.load_config_default([path], None, verbose=False)
        except Exception as e:  # roslaunch's own errors say the file and line
            failures.append(f"{name}: does not load: {e}")
            continue
        if not config.nodes:
            failures.append(f"{name}: no node")
        for node in config.nodes:
            try:
                found = roslib.packages.find_node(node.package, node.type, rospack=rospack)
            except (OSError, rospkg.ResourceNotFound) as e:  # a link to an executable not built
                found = None
                failures.append(f"{name}: node {node.name}: {e}")
                continue
            if not found:
                failures.append(f"{name}: node {node.name}: no executable {node.type} in package {node.package}")
            else:
                print(f"{name}: {node.name} -> {found[0]}")
                failures.extend(f"{name}: node {node.name}: {why}" for why in does_not_start(found[0]))
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
