#include "dem_sampler/app/run_command.hpp"

#include <chrono>
#include <fstream>
#include <iostream>

#include "dem_sampler/cell/overlap_warning.hpp"
#include "dem_sampler/driver/cell_input.hpp"
#include "common/duration_text.hpp"
#include "common/json_input.hpp"
#include "dem_sampler/driver/path_driver.hpp"
#include "dem_sampler/driver/path_input.hpp"
#include "dem_sampler/app/record_table.hpp"

namespace grainbank::app {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void warn_of_large_overlaps(const dem::DemCell& cell) {
  if (const auto warning = dem::large_overlap_warning(cell)) std::cerr << "warning: " << *warning << "\n";
}

void report_preparation(const std::string& stage, long step, const dem::CellMeasures& m) {
  std::cerr << "preparing: " << stage << " step " << step << ", p = " << dem::pressure_of(m.stress)
            << " Pa, phi = " << m.solid_fraction << ", unbalanced force ratio = " << m.unbalanced_force_ratio << "\n";
}

// Reports the fraction done and a linear ETA on stderr, at most five times a second. The report
// overwrites itself ('\r') unless the table goes to the same terminal, where it would garble the rows.
void report_path(long done, long total, Clock::time_point start, Clock::time_point& last_report, bool overwrite) {
  if (done < total && Clock::now() - last_report < std::chrono::milliseconds(200)) return;
  last_report = Clock::now();
  const double elapsed = seconds_since(start);
  const double eta = elapsed * static_cast<double>(total - done) / static_cast<double>(done);
  std::cerr << (overwrite ? "\r" : "") << "path: " << done << "/" << total << " increments ("
            << 100 * done / total << "%), ETA " << common::duration_text(eta) << "   "
            << (done == total || !overwrite ? "\n" : "") << std::flush;
}

// Engine failures (a preparation that does not converge, a diverging cell) say what to change in
// which input file; input errors already name their file.
template <class Work>
auto with_context(const std::filesystem::path& file, Work&& work) {
  try {
    return work();
  } catch (const common::InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
}

}  // namespace

void run_path_command(const RunOptions& options) {
  const std::optional<CellInput> cell_input =
      options.cell_source ? std::nullopt : std::optional<CellInput>(load_cell_input(options.cell_file));
  const PathSpec path = load_path(options.path_file);
  std::ofstream file;
  if (options.out_file) {
    file.open(*options.out_file);
    if (!file) throw common::InputError(options.out_file->string() + ": cannot open for writing");
  }

  const Clock::time_point prepare_start = Clock::now();
  dem::DemCell cell = options.cell_source ? options.cell_source() : with_context(options.cell_file, [&] {
    return build_cell(*cell_input, options.progress ? report_preparation : dem::PreparationObserver{});
  });
  const dem::CellMeasures initial = cell.measures();
  std::cerr << "cell: " << cell.size() << " spheres, phi = " << initial.solid_fraction
            << ", p = " << dem::pressure_of(initial.stress) << " Pa, bonds = " << initial.bonds << " ("
            << (options.cell_source ? options.cell_source_name : cell_input->packing ? "loaded" : "prepared") << " in " << seconds_since(prepare_start) << " s)\n";
  warn_of_large_overlaps(cell);

  RecordTable table(options.out_file ? static_cast<std::ostream&>(file) : std::cout,
                    options.out_file ? TableStyle::csv : TableStyle::aligned);
  table.write_header();
  const long total = increment_count(path);
  const Clock::time_point drive_start = Clock::now();
  Clock::time_point last_report = drive_start - std::chrono::hours(1);
  with_context(options.path_file, [&] {
    drive_along_path(cell, path, [&](const PathRecord& record) {
      table.write(record);
      if (options.progress) report_path(record.index, total, drive_start, last_report, options.out_file.has_value());
    });
  });
  if (options.out_file) {
    file.close();
    if (!file) throw std::runtime_error(options.out_file->string() + ": write failed");
    std::cout << "wrote " << total + 1 << " records to " << options.out_file->string() << "\n";
  }
  std::cerr << "path: " << total << " increments in " << seconds_since(drive_start) << " s\n";
  warn_of_large_overlaps(cell);
}

}  // namespace grainbank::app
