// Shared helpers of the surrogate tests: a small real library sampled in-process with the real
// sampler (the 64-sphere cohesive cell of the sampler tests), re-indexed for the surrogate.
#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>

#include "../sampler/sampler_test_util.hpp"
#include "library_writer.hpp"
#include "paths_input.hpp"
#include "sampler.hpp"
#include "store/path_queue.hpp"
#include "surrogate/reindex.hpp"
#include "template_builder.hpp"

namespace grainbank::surrogate::test {

using sampler::test::TempDir;

// Prepares the template of kCell and samples every path of `paths_json`, as `dem_sampler prepare`
// and `sample --threads 2` do. Throws unless every path is done.
inline void build_library(const TempDir& dir, const std::filesystem::path& library_dir, const std::string& paths_json) {
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
}

}  // namespace grainbank::surrogate::test
