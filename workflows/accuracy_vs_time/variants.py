"""The runs of the accuracy-versus-time study: every knob that trades accuracy for time, one at a time,
against the `live` reference. Each variant is (knob, value, law, material keys, scene settings
{JSON pointer: value}) for plotting.scenes.variant; `preparation` is merged into the cell's
preparation (another number of spheres, another packing seed; the cell is prepared live), `grid_factor`
scales the grid cell size (same domain, same points per cell), `gravity_factor` the scene's gravity.
NOISE_FLOOR is the live run on a cell packed with another seed: what two equally good live runs differ
by, against which every error is stated. CHAOS is the reference itself with gravity changed in its
12th digit: how far the reference's own trajectory moves under a change in the last bits, i.e. which
part of each error no run, however exact its law, could avoid.
A set may come with its own scene and cell (INPUTS); the others run on the demo's column."""
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from plotting.scenes import GRAVITY_PERTURBATION, draw_gravity_factors, drawn_material, hybrid, lookup, surrogate  # noqa: E402  (after the path set-up)


def drawn(name, knob, value, material):
    """The surrogate run `name` and two more draws of it (`name`_draw_1, _draw_2), each on gravity
    changed in its 12th digit and with the length scales fitted on another set of probes (fit_seed K):
    a run of the chaotic flow is one trajectory and the fit is one draw of its scales (stop 63), and
    the error over the three tells the run's bias from its scatter, against CHAOS's."""
    runs = {name: {"knob": knob, "value": value, "law": "surrogate", "material": material}}
    for k, factor in enumerate(draw_gravity_factors(3), start=1):
        runs[f"{name}_draw_{k}"] = {"knob": f"{knob}, another draw", "value": f"gravity × {factor!r}, fit_seed {k}",
                                    "law": "surrogate", "material": drawn_material(material, k),
                                    "gravity_factor": factor}
    return runs


NOISE_FLOOR = "other_seed"
CHAOS = "perturbed"
OTHER_SEED = 1001  # the shipped cells are packed with seed 1

# name: {"knob", "value", "law", "material", "preparation", "grid_factor", "library": "enriched"}
FULL = {
    "live": {"knob": "reference", "value": "live", "law": "live"},
    NOISE_FLOOR: {"knob": "packing seed (noise floor)", "value": OTHER_SEED, "law": "live",
                  "preparation": {"seed": OTHER_SEED}},
    CHAOS: {"knob": "gravity × (1 + 1e-12) (the reference's chaos)", "value": "1+1e-12", "law": "live",
            "gravity_factor": 1 + GRAVITY_PERTURBATION},
    # About the largest Q_t the demo cell's dashpots (restitution 0.3) leave stable, 0.141
    # (substepping.hpp); at 0.2 that cell breaks bonds at rest.
    "q_t_0.14": {"knob": "Q_t", "value": 0.14, "law": "live", "material": {"substepping": {"q_t": 0.14}}},
    "q_t_0.05": {"knob": "Q_t", "value": 0.05, "law": "live", "material": {"substepping": {"q_t": 0.05}}},
    "q_n_200": {"knob": "Q_n", "value": 200, "law": "live", "material": {"substepping": {"q_n": 200}}},
    "q_sigma_0.05": {"knob": "Q_sigma", "value": 0.05, "law": "live", "material": {"substepping": {"q_sigma": 0.05}}},
    "q_sigma_0.5": {"knob": "Q_sigma", "value": 0.5, "law": "live", "material": {"substepping": {"q_sigma": 0.5}}},
    "spheres_64": {"knob": "spheres per cell", "value": 64, "law": "live", "preparation": {"spheres": 64}},
    "hybrid": {"knob": "hybrid (tolerance 1, k 4, warm start)", "value": "", "law": "hybrid", "material": hybrid()},
    "hybrid_tol_0.3": {"knob": "lookup tolerance", "value": 0.3, "law": "hybrid", "material": hybrid(tolerance=0.3)},
    "hybrid_tol_3": {"knob": "lookup tolerance", "value": 3.0, "law": "hybrid", "material": hybrid(tolerance=3.0)},
    # The setting that met 0.1 % front error at ~130x the live speed on the creeping column (CREEPING).
    "hybrid_tol_10": {"knob": "lookup tolerance (return after 5)", "value": 10.0, "law": "hybrid",
                      "material": hybrid(tolerance=10.0, return_after=5)},
    "hybrid_k_1": {"knob": "lookup k", "value": 1, "law": "hybrid", "material": hybrid(k=1)},
    "hybrid_k_8": {"knob": "lookup k", "value": 8, "law": "hybrid", "material": hybrid(k=8)},
    "hybrid_replay": {"knob": "fallback start", "value": "replay", "law": "hybrid", "material": hybrid(start="replay")},
    "cache": {"knob": "cache only", "value": "", "law": "cache", "material": lookup()},
    # The state-keyed surrogate on the same generic library: the demo's law (the demo runs 25 Pa).
    "surrogate": {"knob": "surrogate (tolerance 50 Pa, back after 5)", "value": "", "law": "surrogate",
                  "material": surrogate()},
    "surrogate_tol_25": {"knob": "surrogate tolerance [Pa]", "value": 25.0, "law": "surrogate",
                         "material": surrogate(tolerance_pa=25.0)},
    "surrogate_tol_100": {"knob": "surrogate tolerance [Pa]", "value": 100.0, "law": "surrogate",
                          "material": surrogate(tolerance_pa=100.0)},
    # An error budget per point: no run of small errors drifts unchecked (surrogate_law.hpp). Each
    # tolerance under the budget is drawn three times (drawn()): its bias, told from its scatter.
    **drawn("surrogate_budget_300", "surrogate error budget [Pa] (tolerance 50 Pa)", 300.0,
            surrogate(error_budget_pa=300.0)),
    **{name: spec for tolerance in (25.0, 100.0, 200.0)
       for name, spec in drawn(f"surrogate_tol_{tolerance:g}_budget_300",
                               f"surrogate error budget [Pa] (tolerance {tolerance:g} Pa)", 300.0,
                               surrogate(tolerance_pa=tolerance, error_budget_pa=300.0)).items()},
    # A library of this scene's own states: the second run of a scene (a re-run, a parameter study).
    # `enriching` builds it (hybrid on the bare template: every point live from its first step, the
    # live law to round-off); the runs after it look up in it.
    "enriching": {"knob": "library of this scene", "value": "building it", "law": "hybrid", "library": "enriched",
                  "material": {**hybrid(return_after=0), "enrich": True}},
    "hybrid_enriched": {"knob": "library of this scene", "value": "hybrid, tolerance 10", "law": "hybrid",
                        "library": "enriched", "material": hybrid(tolerance=10.0, return_after=5)},
    "cache_enriched": {"knob": "library of this scene", "value": "cache", "law": "cache", "library": "enriched",
                       "material": lookup()},
    # Last: the finer grid has 4x the points, the costliest run; an interrupted study has the rest.
    "grid_x2": {"knob": "grid cell size", "value": "x2", "law": "live", "grid_factor": 2},
    "grid_x0.5": {"knob": "grid cell size", "value": "x0.5", "law": "live", "grid_factor": 0.5},
}
# The CI smoke test: the reference, its two floors, three variants and a run on the scene's own library.
SMOKE = {name: FULL[name] for name in ("live", NOISE_FLOOR, CHAOS, "q_sigma_0.5", "hybrid", "surrogate", "enriching",
                                       "hybrid_enriched")}
REDUCED = {name: FULL[name] for name in ("live", NOISE_FLOOR, CHAOS, "surrogate", "surrogate_tol_25", "surrogate_tol_100",
                                         *(name for name in FULL if "budget_300" in name), "q_t_0.14", "hybrid",
                                         "hybrid_tol_10", "cache")}
ENRICHED = {name: FULL[name] for name in ("live", NOISE_FLOOR, "hybrid", "enriching", "hybrid_enriched",
                                          "cache_enriched")}

# The former workflows/cache_vs_live: a column of a cell with bonds 20x weaker than
# workflows/scenes/cell_snow_125.json, whose bonds break throughout in the first elastic wave so that
# it creeps as a whole; the library is the bare template (no generic paths) enriched by `enriching`,
# looked up with the library's own key scales (1e-2 strain per key unit, tolerance 0.5) and with fine
# ones. cache_enriched and hybrid_enriched are its former cache_fine and hybrid_wide.
# The material keys are merged into the scene's (RFC 7396), so None (null) removes what a base scene
# may set: its key scales, its fallback.
COARSE_LOOKUP = {"lookup": {"k": 4, "tolerance": 0.5, "scales": None}}
CREEPING = {
    **{name: FULL[name] for name in ("live", NOISE_FLOOR, "enriching")},
    "hybrid_enriched_coarse": {"knob": "library of this scene", "value": "hybrid, library key scales",
                               "law": "hybrid", "library": "enriched",
                               "material": {**COARSE_LOOKUP, "fallback": None, "enrich": False}},
    "cache_enriched_coarse": {"knob": "library of this scene", "value": "cache, library key scales", "law": "cache",
                              "library": "enriched", "material": COARSE_LOOKUP},
    # Negligible increments skipped (integration.skip_strain_increment).
    "hybrid_enriched_skip": {"knob": "library of this scene", "value": "hybrid, library key scales, skip 1e-6",
                             "law": "hybrid", "library": "enriched",
                             "material": {**COARSE_LOOKUP, "fallback": None, "enrich": False},
                             "settings": {"/integration/skip_strain_increment": 1e-6}},
    "hybrid_enriched_tol_1": {"knob": "library of this scene", "value": "hybrid, tolerance 1", "law": "hybrid",
                              "library": "enriched", "material": hybrid()},
    **{name: FULL[name] for name in ("hybrid_enriched", "cache_enriched")},
}
SETS = {"full": FULL, "smoke": SMOKE, "reduced": REDUCED, "enriched": ENRICHED, "creeping": CREEPING}
# Inputs of a set other than the demo's column, soft cell and generic paths (None: no generic paths,
# the library is the template alone).
INPUTS = {"creeping": {"scene": HERE / "creeping_column.json", "cell": HERE / "cell_weak_snow_125.json",
                       "paths": None}}
