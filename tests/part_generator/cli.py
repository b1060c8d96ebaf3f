"""The bead command as the generated parts' tests run it (BEAD_CLI: the
build's; else the installed one)."""
import os
import subprocess

CLI = os.environ.get("BEAD_CLI", "bead")


def run(*args):
    """bead with these arguments; its stdout, asserting it succeeded."""
    done = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout
