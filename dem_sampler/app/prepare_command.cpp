#include "dem_sampler/app/prepare_command.hpp"

#include <iostream>

#include "dem_sampler/driver/cell_input.hpp"
#include "common/json_input.hpp"
#include "database/store/sampler_lock.hpp"
#include "database/store/stale_writer.hpp"
#include "dem_sampler/sampler/template_builder.hpp"

namespace grainbank::app {

void prepare_command(const PrepareOptions& options) {
  const CellInput input = load_cell_input(options.cell_file);
  const bool fresh = !std::filesystem::exists(options.library) || std::filesystem::is_empty(options.library);
  db::Library library = fresh ? db::Library::create(options.library, input.material)
                              : db::Library::open(options.library, input.material);
  const db::SamplerLock lock(options.library);
  db::clear_stale_writer_flags(library);
  const dem::PreparationObserver observer = [](const std::string& stage, long step, const dem::CellMeasures& m) {
    std::cerr << "preparing: " << stage << " step " << step << ", p = " << dem::pressure_of(m.stress)
              << " Pa, phi = " << m.solid_fraction << ", unbalanced force ratio = " << m.unbalanced_force_ratio << "\n";
  };
  sampler::TemplateSummary s;
  try {
    s = sampler::prepare_template(library, "templates", input, options.progress ? observer : dem::PreparationObserver{});
  } catch (const common::InputError&) {
    throw;
  } catch (const db::StoreError&) {
    throw;
  } catch (const std::exception& e) {  // the engine: say which input to change
    throw std::runtime_error(options.cell_file.string() + ": " + e.what());
  }
  std::cout << "template " << s.id << (s.reused ? " (already in the library)" : " (prepared)") << ": N = " << s.spheres
            << ", phi = " << s.solid_fraction << ", Z = " << s.coordination << ", N_b = " << s.bonds
            << ", p = " << s.pressure << " Pa, radii " << s.min_radius << " .. " << s.max_radius << " m (mean "
            << s.mean_radius << " m)\n";
}

}  // namespace grainbank::app
