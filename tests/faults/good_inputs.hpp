// Valid input documents of every JSON type, small and cheap to load: the starting points of the
// table-driven error tests and of the mutation fuzzing (each covers most optional keys, so that
// mutations reach them).
#pragma once

namespace grainbank::faults {

inline const char* const kCell = R"({
  "material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3, "friction": 0.2,
               "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "exponent": 2, "bonding_distance": 0.05},
               "rolling": {"stiffness": 1e-6, "friction": 0.1}},
  "effects": {"cohesion": true, "rolling_resistance": true, "kinetic_stress": false},
  "preparation": {"spheres": 40, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000, "seed": 7,
                  "initial_solid_fraction": 0.2, "pressure_tolerance": 0.02, "q_t": 0.1, "max_steps": 1000}
})";

inline const char* const kPath = R"({
  "segments": [{"L": [[0, 2], [0, 0]], "strain": 0.1}, {"L": [[-1, 0], [0, 1]], "duration": 0.05}],
  "record_interval": 0.01,
  "substepping": {"q_t": 0.1, "q_n": 10, "q_sigma": 0.2}
})";

inline const char* const kPaths = R"({
  "record_interval": 2e-4, "snapshot_interval": 10, "substepping": {"q_t": 0.1, "q_n": 1, "q_sigma": 0.2},
  "paths": [{"segments": [{"L": [[0, 1], [0, 0]], "duration": 0.004}]},
            {"replay": [[[0.5, 0], [0, -0.5]], [[0, 1], [0, 0]]], "record_interval": 1e-4}],
  "generators": [{"count": 3, "start": 2, "rate": {"min": 0.5, "max": 5}, "strain": 0.004, "segments": 2,
                  "changes": ["reversal", "rotation", "fresh"], "volumetric": 0.3, "spin": 0.2}]
})";

inline const char* const kScene = R"({
  "grid": {"origin": [-0.1, 0], "cell_size": 0.05, "cells": [16, 12]},
  "time": {"end": 0.01, "output_interval": 0.005, "series_interval": 0.001, "max_time_step": 1e-3, "cfl": 0.3,
           "contact_factor": 0.2},
  "integration": {"transfer": {"flip_pic": {"pic_rate": 10}}, "sort_interval": 10, "skip_strain_increment": 1e-12},
  "effects": {"gravity": true, "boundary_friction": true},
  "gravity": {"g": [0.5, -9.81], "ramp": {"from": [0, 0], "start": 0, "end": 0.05}},
  "materials": [{"name": "stiff", "law": "elastic", "density": 1500, "young": 2e6, "poisson": 0.25},
                {"name": "soil", "law": "drucker_prager", "density": 1800, "young": 5e5, "poisson": 0.3,
                 "friction_angle": 35, "cohesion": 50, "tensile_strength": 5}],
  "regions": [{"material": "soil", "polygon": [[0.1, 0.1], [0.4, 0.1], [0.1, 0.3]], "points_per_cell": 3},
              {"material": "stiff", "rectangle": {"min": [0.45, 0.1], "max": [0.55, 0.2]}, "velocity": [-0.5, 0]}],
  "obstacles": [{"line": [[-0.1, 0.1], [0.7, 0.1]], "k_n": 1e6, "k_t": 5e5, "friction": 0.4, "damping": 0.3},
                {"polygon": [[0.6, 0.3], [0.65, 0.3], [0.65, 0.35]], "k_n": 1e6, "k_t": 0, "friction": 0,
                 "velocity": [0, -1], "remove_at": 0.005}],
  "tracked_points": [[0.2, 0.15], [0.5, 0.15]]
})";

}  // namespace grainbank::faults
