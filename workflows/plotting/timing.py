"""Running a tool and timing it: wall time, and the CPU time of the process and its children (the
fairer cost on a machine shared with other jobs)."""
import resource
import subprocess
import time


def child_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed_run(command):
    """Runs `command` (its output discarded); returns (wall, CPU seconds, error): error is None, or the
    last line of its stderr when it failed."""
    wall, cpu = time.monotonic(), child_cpu_seconds()
    done = subprocess.run([str(c) for c in command], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    error = None
    if done.returncode != 0:
        error = (done.stderr.strip().splitlines() or [f"exit status {done.returncode}"])[-1]
    return time.monotonic() - wall, child_cpu_seconds() - cpu, error


def timed(command):
    """Runs `command` (its output discarded); returns (wall, CPU) seconds. RuntimeError with its last
    error line when it fails."""
    wall, cpu, error = timed_run(command)
    if error is not None:
        raise RuntimeError(f"{command[0]} failed: {error}")
    return wall, cpu
