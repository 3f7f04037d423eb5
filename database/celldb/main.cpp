// celldb: inspect and maintain a grainbank cell library (DESIGN.md, "Strain-rate paths and the
// library"). Exit codes: 0 success, 1 the library needs attention (verify), 2 error.
#include <CLI/CLI.hpp>
#include <iostream>

#include "celldb/info_command.hpp"
#include "celldb/verify_command.hpp"

int main(int argc, char** argv) {
  using namespace grainbank::celldb;
  CLI::App app{"celldb: inspect and maintain a grainbank cell library (LIB/ = catalogue.sqlite + shards/*.h5)"};
  app.require_subcommand(1);

  InfoOptions info;
  CLI::App* info_cmd = app.add_subcommand("info", "Counts, sizes, material and state-key definition of a library");
  info_cmd->add_option("LIB", info.library, "Library directory")->required();
  info_cmd->add_flag("--json", info.json, "Print the summary as JSON");

  VerifyOptions verify;
  CLI::App* verify_cmd = app.add_subcommand(
      "verify", "Check catalogue against shards: orphans (uncommitted data) and inconsistencies (damaged data)");
  verify_cmd->add_option("LIB", verify.library, "Library directory")->required();
  verify_cmd->add_flag("--repair", verify.repair, "Remove orphans (stop every writer of the library first)");
  verify_cmd->add_flag("--json", verify.json, "Print the report as JSON");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*info_cmd) return run_info(info, std::cout);
    return run_verify(verify, std::cout);
  } catch (const std::exception& e) {
    std::cerr << "celldb: error: " << e.what() << "\n";
    return 2;
  }
}
