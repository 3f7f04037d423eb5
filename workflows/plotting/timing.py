"""Running a tool and timing it: wall time, and the CPU time of the process and its children (the
fairer cost on a machine shared with other jobs)."""
import resource
import subprocess
import time


def child_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed(command):
    """Runs `command` (its output discarded); returns (wall, CPU) seconds. CalledProcessError when it fails."""
    wall, cpu = time.monotonic(), child_cpu_seconds()
    subprocess.run([str(c) for c in command], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    return time.monotonic() - wall, child_cpu_seconds() - cpu
