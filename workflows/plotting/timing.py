"""Running a tool and timing it: wall time, and the CPU time of the process and its children (the
fairer cost on a machine shared with other jobs)."""
import resource
import signal
import subprocess
import threading
import time


def child_cpu_seconds():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _stop_study(signum, frame):
    raise KeyboardInterrupt(f"stopped by signal {signum}")


def timed_run(command):
    """Runs `command` (its output discarded); returns (wall, CPU seconds, error): error is None, or the
    last line of its stderr when it failed.
    A study stopped while the tool runs (Ctrl-C, or SIGTERM to the study) passes the stop on to the
    tool and waits for it to exit, however long that takes: mpm_solver and dem_sampler stop after
    their current step and write their checkpoint, which a tool killed at once (as subprocess.run
    kills it) would lose. (A study killed outright cannot pass anything on: its tool then stops the
    same way on the SIGPIPE of its next progress line.) Then KeyboardInterrupt."""
    wall, cpu = time.monotonic(), child_cpu_seconds()
    process = subprocess.Popen([str(c) for c in command], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               text=True)
    in_main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _stop_study) if in_main_thread else None
    try:
        _, stderr = process.communicate()
    except KeyboardInterrupt:
        process.send_signal(signal.SIGTERM)
        process.communicate()
        raise
    finally:
        if in_main_thread:
            signal.signal(signal.SIGTERM, previous)
    error = None
    if process.returncode != 0:
        error = (stderr.strip().splitlines() or [f"exit status {process.returncode}"])[-1]
    return time.monotonic() - wall, child_cpu_seconds() - cpu, error


def timed(command):
    """Runs `command` (its output discarded); returns (wall, CPU) seconds. RuntimeError with its last
    error line when it fails."""
    wall, cpu, error = timed_run(command)
    if error is not None:
        raise RuntimeError(f"{command[0]} failed: {error}")
    return wall, cpu
