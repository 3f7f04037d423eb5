#!/usr/bin/python3
"""mpm_solver on MPI ranks (issue 14): the paper's live column (workflows/column_collapse, 1152
points) run for a few steps as 1 rank x 1 thread, 1 x 2 and 2 x 1, and a model of the run on 64 to 1024
ranks built from what those runs measured:

    T(P) = S + max over ranks r of sum of c_i over the points i rank r drives + C(P)

- c_i: the seconds per step of point i's live cell (the run's "load" summary);
- S: the rest of a step, replicated on every rank (the MPM itself, the exchange's packing): the 1 x 1
  run's stepping wall time per step minus the sum of the c_i (the same column with an elastic law,
  the MPM alone, is reported beside it as S's floor);
- C(P): the exchange after each stress update, an all-gather of B bytes per point from every rank, plus
  the few scalar all-reduces of a step: K log2(P) latencies alpha and the N B bytes every rank receives
  at bandwidth beta. B is measured (2 x 1 run); alpha and beta are assumptions, stated in the output
  (a cluster's interconnect, not this machine's shared memory).

mpm_solver deals the points out by id (point id mod P) first, then every 50 steps moves cells when
the busiest rank is over 5 % above a greedy deal by measured cost (the costliest first onto the
least-loaded rank): the model gives the deal by id and the greedy deal. The predicted wall time of the seed's column to t = 2.5 s is steps x T(P), with the steps
of the probe's time step: the probe sees the settling column only, before the flow shortens the step
(seed Eq. 4) and re-tiles cells, so it is a lower bound.

  /usr/bin/python3 scaling.py [OUT] [--build BUILD] [--end T] [--smoke]

Writes OUT/scaling.json and OUT/scaling.md, and the runs into OUT/runs/ (OUT default:
build/out/mpi_scaling; workflows/mpi_scaling/results/ holds the committed JSON and table). --smoke runs
three steps (the CI test).
"""
import argparse
import json
import math
import shutil
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting import environment, tables  # noqa: E402  (after the path set-up)
from plotting.timing import timed  # noqa: E402

COLUMN = HERE.parent / "column_collapse" / "column.json"
CONFIGS = [("1x1", 1, 1), ("1x2", 1, 2), ("2x1", 2, 1)]
SIZES = [64, 128, 256, 512, 1024]
SEED_END = 2.5  # s, the seed's column
ALPHA = 2e-6  # s per latency stage of a collective (an InfiniBand-class interconnect)
BETA = 5e9  # bytes/s received per rank
COLLECTIVES_PER_STEP = 6  # stop flag, failure flag, message sizes, messages, time-step minimum, row checks


# The same column with an analytic law: what the MPM alone costs per step, every rank's floor.
ELASTIC = '{"name": "snow", "law": "elastic", "density": 500, "young": 1e6, "poisson": 0.3}'


def run(build, out, ranks, threads, end, extra=()):
    command = [build / "mpm_solver" / "mpm_solver", COLUMN, "--out", out, "--threads", threads,
               "--set", f"/time/end={end}", "--set", "/time/output_interval=1", "--checkpoint-every", "1e9", *extra]
    if ranks > 1:
        command = [shutil.which("mpirun"), "--allow-run-as-root", "--oversubscribe", "-n", ranks] + command
    wall, cpu = timed(command)
    summary = json.loads((out / "summary.json").read_text())
    return {"wall_s": wall, "cpu_s": cpu, "steps": summary["steps"], "final_time": summary["final_time"],
            "stepping_wall_s": summary["wall_time"]["steps"], "load": summary["load"]}


def rank_loads(costs, ranks, balanced):
    """Seconds per step of each rank's points: dealt by id, or largest first onto the least loaded."""
    loads = [0.0] * ranks
    if not balanced:
        for i, c in enumerate(costs):
            loads[i % ranks] += c
        return loads
    for c in sorted(costs, reverse=True):
        k = min(range(ranks), key=loads.__getitem__)
        loads[k] += c
    return loads


def exchange_seconds(ranks, points, bytes_per_point):
    return COLLECTIVES_PER_STEP * ALPHA * math.ceil(math.log2(ranks)) + points * bytes_per_point / BETA


def model(costs, serial, bytes_per_point, ranks, balanced, exchange=None):
    work = max(rank_loads(costs, ranks, balanced))
    comm = exchange_seconds(ranks, len(costs), bytes_per_point) if exchange is None else exchange
    step = serial + work + comm
    one = serial + sum(costs)
    return {"ranks": ranks, "step_s": step, "cells_s": work, "serial_s": serial, "exchange_s": comm,
            "speedup": one / step, "efficiency": one / step / ranks}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", nargs="?", type=Path, default=environment.output_dir("mpi_scaling"))
    parser.add_argument("--build", type=Path, default=environment.build_dir())
    parser.add_argument("--end", type=float, default=4e-3, help="end time of each run [s] (default 4e-3: 20 steps)")
    parser.add_argument("--smoke", action="store_true", help="two steps (the CI test)")
    args = parser.parse_args()
    end = 4e-4 if args.smoke else args.end
    args.out.mkdir(parents=True, exist_ok=True)
    runs = {}
    for name, ranks, threads in CONFIGS:
        runs[name] = run(args.build.resolve(), args.out / "runs" / name, ranks, threads, end) | {"ranks": ranks,
                                                                                         "threads": threads}
        print(f"{name}: {runs[name]['stepping_wall_s']:.1f} s stepping wall, {runs[name]['steps']} steps", flush=True)
    mpm_only = run(args.build.resolve(), args.out / "runs" / "mpm_only", 1, 1, end,
                   ["--set", f"/materials/0={ELASTIC}"])
    one = runs["1x1"]
    for r in runs.values():
        r["speedup"] = one["stepping_wall_s"] / r["stepping_wall_s"]
        r["efficiency"] = r["speedup"] / (r["ranks"] * r["threads"])
    steps = one["steps"]
    costs = one["load"]["point_update_seconds_per_step"]
    # S: all of a step that the cells' own timers do not cover (an upper bound: it includes the cache
    # misses the MPM suffers after each cell update); the elastic column's step is its floor.
    serial = one["stepping_wall_s"] / steps - sum(costs)
    mpm_only_step = mpm_only["stepping_wall_s"] / mpm_only["steps"]
    two = runs["2x1"]
    bytes_per_point = two["load"]["shared_bytes_per_step"] / len(costs)
    # The check: the model with the 2-rank run's own exchange (this machine's shared memory) against
    # the 2-rank measurement. The exchange time there is what the step took beyond the busier rank's cells.
    two_step = two["stepping_wall_s"] / two["steps"]
    two_cells = max(two["load"]["update_seconds_by_rank"]) / two["steps"]
    check = model(costs, serial, bytes_per_point, 2, False, exchange=0.0)
    check |= {"measured_step_s": two_step, "measured_busier_rank_cells_s": two_cells,
              "measured_exchange_and_waits_s": two_step - two_cells - serial}
    dt = one["final_time"] / steps
    projection = []
    for p in SIZES:
        for balanced in (False, True):
            m = model(costs, serial, bytes_per_point, p, balanced)
            m |= {"placement": "cost-aware" if balanced else "by id", "seed_column_wall_h": m["step_s"] * SEED_END / dt / 3600}
            projection.append(m)
    mean = sum(costs) / len(costs)
    spread = math.sqrt(sum((c - mean) ** 2 for c in costs) / len(costs)) / mean
    result = {"scene": str(COLUMN), "points": len(costs), "end_s": end, "probe_dt_s": dt, "runs": runs,
              "cell_cost_s": {"mean": mean, "cv": spread, "max_over_mean": max(costs) / mean},
              "serial_s_per_step": serial, "mpm_only_s_per_step": mpm_only_step,
              "bytes_per_point_per_step": bytes_per_point,
              "assumed": {"alpha_s": ALPHA, "beta_bytes_per_s": BETA, "collectives_per_step": COLLECTIVES_PER_STEP},
              "model_check_2_ranks": check, "projection": projection}
    for r in runs.values():
        del r["load"]["point_update_seconds_per_step"]
    (args.out / "scaling.json").write_text(json.dumps(result, indent=2) + "\n")
    run_rows = [{"run": n, "stepping wall [s]": r["stepping_wall_s"], "CPU [s]": r["cpu_s"], "speed-up": r["speedup"],
                 "efficiency": r["efficiency"], "bytes exchanged / step": r["load"]["shared_bytes_per_step"]}
                for n, r in runs.items()]
    model_rows = [{"ranks": m["ranks"], "placement": m["placement"], "step [ms]": m["step_s"] * 1e3,
                   "cells [ms]": m["cells_s"] * 1e3, "S [ms]": m["serial_s"] * 1e3, "exchange [ms]": m["exchange_s"] * 1e3,
                   "efficiency": m["efficiency"], "seed column to 2.5 s [h]": m["seed_column_wall_h"]} for m in projection]
    lines = [f"Live column, {len(costs)} points, {steps} steps of {dt:.3g} s (run to t = {end} s).", "",
             tables.markdown(run_rows, {"speed-up": ".2f", "efficiency": ".0%", "bytes exchanged / step": ".0f"}),
             f"Cell cost per step: mean {mean * 1e3:.2f} ms, spread (CV) {spread:.2f}, max/mean "
             f"{max(costs) / mean:.2f}; replicated part S = {serial * 1e3:.2f} ms per step (the same column with an "
             f"elastic law: {mpm_only_step * 1e3:.2f} ms per step); "
             f"{bytes_per_point:.0f} bytes per point per step.", "",
             f"Model check, 2 ranks: predicted {check['step_s'] * 1e3:.1f} ms per step without the exchange, measured "
             f"{two_step * 1e3:.1f} ms (exchange and waits {check['measured_exchange_and_waits_s'] * 1e3:.1f} ms).", "",
             tables.markdown(model_rows, {"efficiency": ".0%", "exchange [ms]": ".3f"}),
             f"Assumed interconnect: {ALPHA * 1e6:.0f} µs per latency stage, {BETA / 1e9:.0f} GB/s per rank."]
    (args.out / "scaling.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
