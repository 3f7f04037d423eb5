#include "dem_sampler/app/sample_command.hpp"

#include <unistd.h>

#include <csignal>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "dem_sampler/sampler/paths_input.hpp"
#include "dem_sampler/app/sample_progress.hpp"
#include "dem_sampler/sampler/sampler.hpp"
#include "dem_sampler/sampler/stored_path.hpp"
#include "dem_sampler/app/test_stop_point.hpp"
#include "common/stop_signals.hpp"
#include "database/store/path_queue.hpp"
#include "database/store/sampler_lock.hpp"
#include "database/store/stale_writer.hpp"
#ifdef GRAINBANK_HAVE_MPI
#include "dem_sampler/sampler/mpi_work_source.hpp"
#endif

namespace grainbank::app {
namespace {

using common::install_stop_signals;
using common::stop_signal;

// What rank 0 (or the only process) sets up before any path runs. Holds the sampler lock.
struct Setup {
  db::Library library;
  std::unique_ptr<db::SamplerLock> lock;
  std::vector<std::int64_t> pending;
  long expected_records = 0;
};

std::int64_t choose_template(db::Library& library, const SampleOptions& options) {
  if (options.template_id) {
    library.catalogue().template_row(*options.template_id);  // throws naming the catalogue if absent
    return *options.template_id;
  }
  const std::vector<db::TemplateRow> templates = library.catalogue().templates();
  if (templates.empty())
    throw db::StoreError(library.directory(), "the library has no template: run dem_sampler prepare CELL.json --library " +
                                                  library.directory().string() + " first");
  if (templates.size() > 1)
    throw db::StoreError(library.directory(), "the library has " + std::to_string(templates.size()) +
                                                  " templates: choose one with --template ID");
  return templates.front().id;
}

Setup set_up(const SampleOptions& options) {
  // Everything that can be wrong with the inputs is found before the library is written to.
  const std::vector<sampler::PathPlan> plans = sampler::load_paths_file(options.paths_file);
  Setup setup{db::Library::open(options.library), nullptr, {}, 0};
  db::Library& library = setup.library;
  const std::int64_t template_id = choose_template(library, options);
  const double restitution = library.material().contact.restitution;
  for (std::size_t k = 0; k < plans.size(); ++k)
    if (const auto error = dem::time_step_factor_error(plans[k].path.substepping.q_t, restitution))
      throw common::InputError(options.paths_file.string() + ": planned path " + std::to_string(k + 1) + " of " +
                               std::to_string(plans.size()) + ": substepping.q_t: " + *error +
                               " (the library's material)");
  setup.lock = std::make_unique<db::SamplerLock>(options.library);

  db::Catalogue& catalogue = library.catalogue();
  // We hold the lock, so no other sampler is running: `running` rows are left by a killed one.
  if (const std::int64_t stale = db::reset_running_paths(catalogue))
    std::cerr << "reset " << stale << " path(s) left running by an interrupted sampler to pending\n";
  db::clear_stale_writer_flags(library);
  if (options.retry_failed)
    std::cerr << "retrying " << db::retry_failed_paths(catalogue) << " failed path(s)\n";
  long added = 0;
  {
    db::SqliteTransaction transaction(catalogue.connection());
    for (const sampler::PathPlan& plan : plans) {
      const nlohmann::json spec = sampler::to_json(plan);
      if (db::find_path(catalogue, template_id, spec.dump())) continue;
      library.add_path(template_id, spec, library.material());
      ++added;
    }
    transaction.commit();
  }
  for (std::int64_t id : db::pending_paths(catalogue)) {
    try {
      const std::optional<sampler::PathPlan> plan = sampler::stored_plan(library, catalogue.path(id));
      setup.expected_records += plan ? sampler::record_count(*plan) : 0;
      setup.pending.push_back(id);
    } catch (const common::InputError& e) {
      // A spec an older build registered without reading it back: it fails alone, with its reason,
      // instead of stopping this and every later run of the library.
      catalogue.finish_path(id, db::PathStatus::failed, 0, std::string("its stored spec cannot be run: ") + e.what());
      std::cerr << "path " << id << ": its stored spec cannot be run, marked failed: " << e.what() << "\n";
    }
  }
  std::cerr << options.paths_file.string() << ": " << plans.size() << " path(s), " << added << " new on template "
            << template_id << "; " << setup.pending.size() << " pending path(s) in the library\n";
  return setup;
}

sampler::SampleObserver observe(SampleProgress& progress, TestStopPoint& stop_point) {
  return {[&progress, &stop_point](long n) {
            progress.commit(n);
            stop_point.committed(n);
          },
          [&progress](const sampler::PathOutcome& o) { progress.path(o); }};
}

int report(const sampler::SampleSummary& s, const std::string& where) {
  std::cout << "sampled " << (s.done + s.failed) << " path(s) " << where << ": " << s.done << " done, " << s.failed
            << " failed; " << s.records << " records in " << s.seconds << " s ("
            << (s.seconds > 0 ? static_cast<double>(s.records) / s.seconds : 0) << " records/s, "
            << (s.seconds > 0 ? s.particle_steps / s.seconds : 0) << " particle-steps/s, "
            << (s.records > 0 ? static_cast<double>(s.dem_steps) / static_cast<double>(s.records) : 0)
            << " DEM steps per record)\n";
  if (s.failed) std::cout << s.failed << " path(s) failed: their error is in the catalogue (paths.error)\n";
  if (!stop_signal()) return 0;
  std::cerr << "dem_sampler: interrupted by " << strsignal(stop_signal()) << ": " << s.abandoned
            << " path(s) in progress put back to pending; run the same command again to resume\n";
  return 1;
}

int sample_serial(const SampleOptions& options) {
  TestStopPoint stop_point;
  Setup setup = set_up(options);
  stop_point.committed(0);
  db::ShardWriter shard(setup.library, "rank0");
  sampler::LibraryWriter writer(setup.library, shard);
  sampler::ListWorkSource source(setup.pending);
  sampler::SampleOptions run;
  run.threads = options.threads.value_or(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  run.commit_batch = options.commit_batch;
  run.stop = &install_stop_signals();
  SampleProgress progress(static_cast<long>(setup.pending.size()), setup.expected_records, isatty(STDERR_FILENO));
  const sampler::SampleSummary summary = sampler::run_paths(writer, source, run, observe(progress, stop_point));
  progress.finish();
  return report(summary, "on " + std::to_string(run.threads) + " thread(s)");
}

#ifdef GRAINBANK_HAVE_MPI
int sample_mpi(const SampleOptions& options) {
  const common::MpiSession mpi(nullptr, nullptr);
  const bool root = mpi.rank() == 0;
  TestStopPoint stop_point;
  std::optional<Setup> setup;
  std::string error;
  if (root) {
    try {
      setup.emplace(set_up(options));
      stop_point.committed(0);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  if (!mpi.all(error.empty())) {
    if (root) std::cerr << "dem_sampler: " << error << "\n";
    return 1;
  }
  db::Library library = root ? std::move(setup->library) : db::Library::open(options.library);
  sampler::SampleOptions run;
  run.threads = options.threads.value_or(1);
  run.commit_batch = options.commit_batch;
  run.stop = &install_stop_signals();
  sampler::SampleSummary local;
  {
    db::ShardWriter shard(library, "rank" + std::to_string(mpi.rank()));
    sampler::LibraryWriter writer(library, shard);
    std::unique_ptr<sampler::WorkSource> source;
    if (root)
      source = std::make_unique<sampler::MpiDispatcher>(setup->pending, mpi.size(), run.stop);
    else
      source = std::make_unique<sampler::MpiClient>();
    SampleProgress progress(root ? static_cast<long>(setup->pending.size()) : 0, 0, false,
                            "rank " + std::to_string(mpi.rank()) + ": ");
    try {
      local = sampler::run_paths(writer, *source, run, observe(progress, stop_point));
    } catch (const std::exception& e) {
      error = e.what();
    }
    // Destroying the source lets rank 0's dispatcher finish before the collectives below.
  }
  if (!error.empty()) std::cerr << "dem_sampler: rank " << mpi.rank() << ": " << error << "\n";
  const sampler::SampleSummary total = sampler::combine_over_ranks(local);
  const bool ok = mpi.all(error.empty());
  if (!root) return ok && !stop_signal() ? 0 : 1;
  const int code = report(total, "on " + std::to_string(mpi.size()) + " MPI rank(s) x " + std::to_string(run.threads) +
                                     " thread(s)");
  return ok ? code : 1;
}
#endif

}  // namespace

int sample_command(const SampleOptions& options) {
#ifdef GRAINBANK_HAVE_MPI
  if (common::MpiSession::launched_by_mpirun()) return sample_mpi(options);
#endif
  return sample_serial(options);
}

}  // namespace grainbank::app
