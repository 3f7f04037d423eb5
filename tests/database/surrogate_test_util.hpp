// Shared helpers of the surrogate tests: a small real library sampled in-process with the real
// sampler (the 64-sphere cohesive cell of the sampler tests), re-indexed for the surrogate.
#pragma once
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "tests/sampler/sampler_test_util.hpp"
#include "dem_sampler/sampler/library_writer.hpp"
#include "dem_sampler/sampler/paths_input.hpp"
#include "dem_sampler/sampler/sampler.hpp"
#include "database/store/path_queue.hpp"
#include "database/surrogate/length_scales.hpp"
#include "database/surrogate/reindex.hpp"
#include "database/surrogate/surrogate_index.hpp"
#include "dem_sampler/sampler/template_builder.hpp"

namespace grainbank::surrogate::test {

using sampler::test::TempDir;

// Forty generated two-segment paths (reversals and turns of the principal axes, volumetric and
// deviatoric, with spin), 0.4 % strain each at 1-3 /s: ~540 intervals, about 2 s to sample; a
// snapshot every fifth record (what a state warm start starts from).
inline const char* const kGeneralPaths = R"({
  "record_interval": 2e-4, "snapshot_interval": 5,
  "generators": [{"count": 40, "rate": {"min": 1, "max": 3}, "strain": 0.004, "segments": 2,
                  "changes": ["reversal", "rotation"], "volumetric": 0.5, "spin": 0.2}]
})";

// The in-plane stress and σ_zz of a state: what the surrogate answers (rate_answer.hpp carries the
// out-of-plane shears without predicting them).
inline dem::Mat3 answered_part(const dem::Mat3& stress) {
  dem::Mat3 s = stress;
  s(0, 2) = s(2, 0) = s(1, 2) = s(2, 1) = 0;
  return s;
}

// An index over `dataset` with length scales fitted on it.
inline std::unique_ptr<SurrogateIndex> fitted_index(const Dataset& dataset, const SurrogateOptions& options = {}) {
  const LengthScaleFit fit = fit_length_scales(dataset.constants, dataset.samples, options);
  auto index = std::make_unique<SurrogateIndex>(dataset.constants, fit.scales, options);
  index->insert(dataset.samples);
  return index;
}

// Prepares the template of kCell and samples every path of `paths_json`, as `dem_sampler prepare`
// and `sample --threads 2` do, and returns the library. Throws unless every path is done.
inline db::Library build_library(const TempDir& dir, const std::filesystem::path& library_dir, const std::string& paths_json) {
  const app::CellInput input = app::load_cell_input(dir.write("cell.json", sampler::test::kCell));
  db::Library library = db::Library::create(library_dir, input.material);
  const std::int64_t template_id = sampler::prepare_template(library, "templates", input).id;
  const auto plans = sampler::load_paths_file(dir.write("paths.json", paths_json));
  for (const sampler::PathPlan& plan : plans) library.add_path(template_id, sampler::to_json(plan), library.material());
  db::ShardWriter shard(library, "rank0");
  sampler::LibraryWriter writer(library, shard);
  sampler::ListWorkSource source(db::pending_paths(library.catalogue()));
  sampler::SampleOptions options;
  options.threads = 2;
  const sampler::SampleSummary summary = sampler::run_paths(writer, source, options);
  if (summary.done != static_cast<long>(plans.size()))
    throw std::runtime_error("the surrogate test library sampled " + std::to_string(summary.done) + " of " +
                             std::to_string(plans.size()) + " paths");
  return library;
}

}  // namespace grainbank::surrogate::test
