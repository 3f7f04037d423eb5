#include "dem_sampler/app/rheometer_command.hpp"

#include <chrono>
#include <fstream>
#include <iostream>

#include "common/json_input.hpp"
#include "dem_sampler/cell/shear_rheometer.hpp"
#include "dem_sampler/driver/cell_input.hpp"

namespace grainbank::app {

void rheometer_command(const RheometerOptions& options) {
  const CellInput input = load_cell_input(options.cell_file);
  const auto fail = [&](const std::string& what) { throw common::InputError(options.cell_file.string() + ": " + what); };
  if (!options.normal_stress && !input.preparation)
    fail("a packing file has no preparation pressure: give --pressure");
  dem::RheometerSettings settings;
  settings.normal_stress = options.normal_stress ? *options.normal_stress : input.preparation->pressure;
  settings.strain = options.strain;
  settings.steady_from = options.steady_from;
  std::ofstream file;
  if (options.out_file) {
    file.open(*options.out_file);
    if (!file) throw common::InputError(options.out_file->string() + ": cannot open for writing");
  }
  std::ostream& out = options.out_file ? static_cast<std::ostream&>(file) : std::cout;
  out.precision(10);
  out << "I,shear_rate,mu,mu_error,normal_stress,phi,Z,steps,peak_shear,peak_strain,phi_consolidated\n";

  dem::DemCell prepared = [&] {
    try {
      return build_cell(input);
    } catch (const common::InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw std::runtime_error(options.cell_file.string() + ": " + e.what());
    }
  }();
  for (double inertial_number : options.inertial_numbers) {
    settings.inertial_number = inertial_number;
    dem::DemCell cell = prepared;
    const auto start = std::chrono::steady_clock::now();
    const dem::RheometerResult r = dem::shear_at_inertial_number(cell, settings);
    out << r.inertial_number << ',' << r.shear_rate << ',' << r.friction << ',' << r.friction_error << ','
        << r.normal_stress << ',' << r.solid_fraction << ',' << r.coordination << ',' << r.steps << ',' << r.peak_shear << ','
        << r.peak_strain << ',' << r.consolidated_solid_fraction << '\n'
        << std::flush;
    std::cerr << "I = " << inertial_number << ": mu = " << r.friction << " ± " << r.friction_error << ", phi = "
              << r.solid_fraction << " (" << r.steps << " steps, "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s)\n";
  }
  if (options.out_file) {
    file.close();
    if (!file) throw std::runtime_error(options.out_file->string() + ": write failed");
  }
}

}  // namespace grainbank::app
