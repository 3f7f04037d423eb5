// celldb: inspect and maintain a grainbank cell library (DESIGN.md, "Strain-rate paths and the
// library", "Nearest-state lookup"). Exit codes: 0 success, 1 the library needs attention (verify,
// audit) or cannot answer (query on an empty library), 2 error.
#include <CLI/CLI.hpp>
#include <iostream>

#include "database/celldb/audit_command.hpp"
#include "database/celldb/bench_command.hpp"
#include "database/celldb/export_command.hpp"
#include "database/celldb/info_command.hpp"
#include "database/celldb/merge_command.hpp"
#include "database/celldb/prune_command.hpp"
#include "database/celldb/query_command.hpp"
#include "database/celldb/verify_command.hpp"

int main(int argc, char** argv) {
  using namespace grainbank::celldb;
  CLI::App app{"celldb: inspect and maintain a grainbank cell library (LIB/ = catalogue.sqlite + shards/*.h5)"};
  app.require_subcommand(1);

  InfoOptions info;
  CLI::App* info_cmd =
      app.add_subcommand("info", "Counts, sizes, material, state-key definition and key-space coverage of a library");
  info_cmd->add_option("LIB", info.library, "Library directory")->required();
  info_cmd->add_flag("--json", info.json, "Print the summary as JSON");

  VerifyOptions verify;
  CLI::App* verify_cmd = app.add_subcommand(
      "verify", "Check catalogue against shards: orphans (uncommitted data) and inconsistencies (damaged data)");
  verify_cmd->add_option("LIB", verify.library, "Library directory")->required();
  verify_cmd->add_flag("--repair", verify.repair, "Remove orphans (stop every writer of the library first)");
  verify_cmd->add_flag("--json", verify.json, "Print the report as JSON");

  QueryOptions query;
  CLI::App* query_cmd = app.add_subcommand("query", "Nearest-state answer (stress, distance, hit, estimated error)");
  query_cmd->add_option("LIB", query.library, "Library directory")->required();
  query_cmd->add_option("--state", query.state, R"(JSON text or file: {"F": [[..],[..]], "L": [[..],[..]], "D": 0})")
      ->required();
  query_cmd->add_option("--k", query.lookup.k, "Neighbours blended")->capture_default_str()->check(CLI::PositiveNumber);
  query_cmd->add_option("--tolerance", query.lookup.tolerance, "Hit when the nearest record is this close (key units)")
      ->capture_default_str();
  query_cmd->add_flag("--json", query.json, "Print the answer as JSON");

  MergeOptions merge;
  CLI::App* merge_cmd = app.add_subcommand("merge", "Add the done paths of other libraries or of their shards");
  merge_cmd->add_option("LIB", merge.library, "Target library directory")->required();
  merge_cmd->add_option("SHARD_OR_LIB", merge.sources, "Source library directories or LIB2/shards/<name>.h5")
      ->required();

  ExportOptions export_options;
  CLI::App* export_cmd = app.add_subcommand("export", "Committed records as CSV, one file per path");
  export_cmd->add_option("LIB", export_options.library, "Library directory")->required();
  export_cmd->add_option("--csv", export_options.csv_directory, "Output directory")->required();

  BenchOptions bench;
  CLI::App* bench_cmd = app.add_subcommand("bench", "Lookup, insert and open timings on a synthetic library");
  bench_cmd->add_option("--records", bench.records, "Records in the synthetic library")->capture_default_str();
  bench_cmd->add_option("--k", bench.k, "Neighbours per query")->capture_default_str();
  bench_cmd->add_option("--queries", bench.queries, "kd-tree queries timed")->capture_default_str();
  bench_cmd->add_option("--brute-queries", bench.brute_queries, "Brute-force queries timed")->capture_default_str();
  bench_cmd->add_option("--far-share", bench.far_share, "Share of queries anywhere in the sampled region (misses)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  bench_cmd->add_flag("--uniform", bench.uniform, "Uniformly random states instead of paths");
  bench_cmd->add_flag("--json", bench.json, "Print the figures as JSON");

  PruneOptions prune;
  CLI::App* prune_cmd = app.add_subcommand(
      "prune", "Cut the snapshots to a budget per path (records and templates are kept); needs the sampler lock");
  prune_cmd->add_option("LIB", prune.library, "Library directory")->required();
  prune_cmd->add_option("--keep-per-path", prune.keep_per_path, "Snapshots each path keeps (first, last, evenly between)")
      ->required()
      ->check(CLI::NonNegativeNumber);
  prune_cmd->add_flag("--dry-run", prune.dry_run, "Report what would be removed; change nothing");

  AuditCommandOptions audit;
  CLI::App* audit_cmd = app.add_subcommand(
      "audit", "Replay sampled records (determinism), leave-one-path-out lookup errors, error vs distance");
  audit_cmd->add_option("LIB", audit.library, "Library directory")->required();
  audit_cmd->add_option("--samples", audit.audit.sample.records, "Records replayed (drawn among the audited paths' records)")
      ->capture_default_str();
  audit_cmd->add_option("--paths", audit.audit.sample.paths, "Done paths audited (one lookup index is built without each)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  audit_cmd->add_option("--seed", audit.audit.sample.seed, "Seed of the draw")->capture_default_str();
  audit_cmd->add_option("--k", audit.audit.lookup.k, "Neighbours blended by the lookup")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  audit_cmd->add_option("--tolerance", audit.audit.lookup.tolerance, "Lookup tolerance whose hits are reported (key units)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  audit_cmd->add_option("--target", audit.audit.target, "Relative error the suggested tolerance keeps (p95 of hits)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  audit_cmd->add_option("--replay-tolerance", audit.audit.replay_tolerance,
                        "Relative stress difference above which a replayed record is flagged")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  audit_cmd->add_option("--out", audit.out, "Output directory (default LIB/audits/<UTC time>)");
  audit_cmd->add_flag("--json", audit.json, "Print the summary as JSON");
  audit_cmd->add_flag("--plots", audit.plots, "Draw the PNG figures (python3 + matplotlib)");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*info_cmd) return run_info(info, std::cout);
    if (*verify_cmd) return run_verify(verify, std::cout);
    if (*query_cmd) return run_query(query, std::cout);
    if (*merge_cmd) return run_merge(merge, std::cout);
    if (*export_cmd) return run_export(export_options, std::cout);
    if (*prune_cmd) return run_prune(prune, std::cout);
    if (*audit_cmd) return run_audit(audit, std::cout);
    return run_bench(bench, std::cout);
  } catch (const std::exception& e) {
    std::cerr << "celldb: error: " << e.what() << "\n";
    return 2;
  }
}
