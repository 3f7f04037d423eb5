"""Shared helpers of the workflow scripts: their environment (`environment`, as workflows/env.sh),
scene variants (`scenes`, through `mpm_solver scene`), reading mpm_solver outputs and drawing PNG
figures.

Scripts under workflows/<job>/ put workflows/ on sys.path and import `plotting.<module>`. The readers
need only the standard library and numpy; `figures` needs matplotlib (python3-matplotlib on Debian).
"""
