// A surrogate dataset from a cell library as it is (issue 13: "existing libraries already hold σ,
// L, F, D, φ and Z per interval, so they can be re-indexed without resampling").
//
// Promises:
// - Record k+1 of a path stores the L imposed over the interval from record k (record 0 has none;
//   dem_sampler/sampler/path_runner.cpp), so the interval k → k+1 gives the sample
//   make_sample(state of record k, state of record k+1, L of record k+1, t_{k+1} − t_k).
//   Intervals with Δt ≤ 0 or sym L = 0 (rests, pure spins) carry no rate per |D| and are skipped.
// - With a span s > 1 the sample of interval k reaches further, to record min(k + s, j), j the last
//   record of the run of intervals that share interval k's L: its answer is the mean rate over up to
//   s intervals of one L, so a stored interval still starts each sample and no sample crosses a
//   change of loading. Why: a small cell's stress fluctuates from record to record by about as much
//   as it changes in flow (the 125-sphere soft-snow cell in steady shear at 1 kPa and 3 /s: 71 Pa
//   rms per 0.1 ms against a mean change of zero). A cell of another packing fluctuates as much, so the
//   fluctuation is not what the surrogate should learn, nor what its error estimate should count;
//   averaged over s intervals it falls about s times.
//   On a pressure-controlled segment (path_input.hpp: the in-plane isotropic part of L is servoed at
//   every increment, so no two records share L) the intervals of the segment count as one loading,
//   and the sample's L is their time-weighted mean, as a live point's learned span takes the mean L
//   of its steps. Until stop 50 such a segment, a flow at its critical state, gave one-interval
//   samples only: its fluctuation, unaveraged.
// - reindex gives one sample per key: of the samples whose keys are equal to the bit, it keeps the
//   one whose answer spans the most intervals (the first in library order among equals). Paths that
//   share a first segment repeat its records to the bit (the sampler is deterministic): the state
//   probes of one base at several depths and rates do. Why: a repeated key is one measurement, not
//   several. Counted twice, a repeat is predicted by its copy in the fit's leave-one-out, so the
//   error estimate near the template (where every standing point starts) took it as confirmed.
//   And a path whose loading changes after one interval gives that key a one-interval answer beside
//   the longer paths' spanned ones: on the generalization library it was 5.2 times stiffer (stop
//   62), and the fit took both.
// - Only committed records of `done` paths are read (as the nearest-state index does); nothing is
//   written to the library.
// - The constants come from the library itself: p_ref the mean pressure of its templates (the
//   pressure they were prepared at), p_floor = pressure_floor · p_ref (default kPressureFloor =
//   0.1), d the mean grain diameter of its templates, ρ its material's grain density. The floor is
//   high on purpose: a cohesive cell near or in tension gets its stiffness from its bonds, not from
//   p, and normalizing by p_ref/100 made the answers of such states a hundred times those of
//   compressed ones (measured on a sampled library). Below its preparation pressure a packing is
//   overconsolidated: it unloads at the stiffness its contacts and bonds were made with (the
//   generalization study's bonded cell goes from 200 Pa to 200 Pa of tension at one slope), so
//   pressure_floor = 1 makes an elastic unloading one answer at every pressure below p_ref, where
//   with 0.1 its answer grows as 1/p down to the floor and a point unloaded from p_ref slows as it
//   nears p_floor, breaking bonds its cell keeps. What each gives and costs on the generalization
//   study's columns: docs/surrogate.md, "Stop 67".
#pragma once
#include <string>
#include <vector>

#include "database/surrogate/sample.hpp"
#include "database/store/record.hpp"

namespace grainbank::db {
class Library;
}

namespace grainbank::surrogate {

struct Dataset {
  FeatureConstants constants;
  std::vector<Sample> samples;
};

PointState point_state(const db::Record& record);

// [begin, end] [s, from the path's start] of one pressure-controlled segment of a stored path.
struct HeldSegment {
  double begin = 0, end = 0;
};

// The pressure-controlled segments of a path's canonical spec (PathRow::spec; none for a replay).
std::vector<HeldSegment> held_segments(const std::string& spec);

inline constexpr double kPressureFloor = 0.1;  // p_floor / p_ref unless a law asks for another

// Throws db::StoreError when the library has no template, std::invalid_argument unless
// pressure_floor (p_floor / p_ref) is in (0, 1].
FeatureConstants library_constants(db::Library& library, double pressure_floor = kPressureFloor);

// The samples of the library's done paths, each spanning up to `span` ≥ 1 intervals, one per key,
// keyed and normalized with library_constants(library, pressure_floor).
Dataset reindex(db::Library& library, std::size_t span = 1, double pressure_floor = kPressureFloor);

}  // namespace grainbank::surrogate
