#include "mpm_solver/io/restart.hpp"

#include <limits>
#include <stdexcept>
#include <string>

#include "dem_sampler/cell/dem_cell.hpp"
#include "database/store/cell_state_io.hpp"
#include "database/store/hdf5_handle.hpp"

namespace grainbank::mpm::io {

namespace h5 = db::h5;

namespace {

constexpr const char* kFormat = kRestartFormat;
constexpr hsize_t kColumns = kRestartPointColumns;

// id, law, slot, mass, V0, V, radius, x, y, vx, vy, F (4), L (4), σ in plane (4), σ_zz, pending
// increment (4), its time, APIC's affine velocity B (4).
void append_row(std::vector<double>& rows, const MaterialPoint& mp) {
  const Mat2& F = mp.deformation_gradient;
  const Mat2& L = mp.velocity_gradient;
  const Mat2& s = mp.stress.in_plane;
  const Mat2& P = mp.pending_increment;
  const Mat2& B = mp.affine_velocity;
  rows.insert(rows.end(), {double(mp.id), double(mp.law), double(mp.slot), mp.mass, mp.initial_volume, mp.volume,
                           mp.radius, mp.position.x(), mp.position.y(), mp.velocity.x(), mp.velocity.y(), F(0, 0),
                           F(0, 1), F(1, 0), F(1, 1), L(0, 0), L(0, 1), L(1, 0), L(1, 1), s(0, 0), s(0, 1), s(1, 0),
                           s(1, 1), mp.stress.zz, P(0, 0), P(0, 1), P(1, 0), P(1, 1), mp.pending_time, B(0, 0), B(0, 1),
                           B(1, 0), B(1, 1)});
}

MaterialPoint point_from_row(const double* r) {
  MaterialPoint mp;
  mp.id = static_cast<std::uint32_t>(r[0]);
  mp.law = static_cast<std::uint32_t>(r[1]);
  mp.slot = static_cast<std::uint32_t>(r[2]);
  mp.mass = r[3], mp.initial_volume = r[4], mp.volume = r[5], mp.radius = r[6];
  mp.position = {r[7], r[8]};
  mp.velocity = {r[9], r[10]};
  mp.deformation_gradient << r[11], r[12], r[13], r[14];
  mp.velocity_gradient << r[15], r[16], r[17], r[18];
  mp.stress.in_plane << r[19], r[20], r[21], r[22];
  mp.stress.zz = r[23];
  mp.pending_increment << r[24], r[25], r[26], r[27];
  mp.pending_time = r[28];
  mp.affine_velocity << r[29], r[30], r[31], r[32];
  return mp;
}

// A law's entries are prefixed "law_<index>_", so two laws may use the same names.
class LawEntries : public LawStateWriter, public LawStateReader {
 public:
  LawEntries(const h5::Object& root, std::size_t law) : root_(root), prefix_("law_" + std::to_string(law) + "_") {}

  void write_table(const std::string& name, const std::vector<double>& rows, std::size_t columns) override {
    h5::write_array(root_, prefix_ + name, rows, columns);
  }
  void write_cell(const std::string& name, const dem::DemCell& cell) override {
    db::write_cell_state(h5::create_group(root_, prefix_ + name), db::StoredCell{cell.state(), cell.skin()});
  }
  std::vector<double> read_table(const std::string& name, std::size_t columns) override {
    return h5::read_array<double>(root_, prefix_ + name, columns);
  }
  bool has_table(const std::string& name) override { return h5::has_child(root_, prefix_ + name); }
  dem::CellState read_cell(const std::string& name) override {
    return db::read_cell_state(h5::open_group(root_, prefix_ + name)).state;
  }

 private:
  const h5::Object& root_;
  std::string prefix_;
};

// One per-point history of every obstacle (tangential forces, forces held at a release's start) as an
// obstacles × points table, `fill` past the points an obstacle keeps a history for.
void write_obstacle_table(const h5::Object& root, const std::string& name, const Solver& solver,
                          const std::vector<double>& (Obstacle::*history)() const, double fill) {
  std::vector<double> table;
  for (const Obstacle& o : solver.obstacles()) {
    std::vector<double> row = (o.*history)();
    row.resize(solver.points().size(), fill);
    table.insert(table.end(), row.begin(), row.end());
  }
  h5::write_array(root, name, table, solver.points().size());
}

// Such a table read back, a row per obstacle; throws when its shape is not the scene's.
std::vector<std::vector<double>> read_obstacle_table(const h5::Object& root, const std::string& name,
                                                     const std::filesystem::path& file, std::size_t obstacles,
                                                     std::size_t points) {
  const std::vector<double> table = h5::read_array<double>(root, name, points);
  if (table.size() != obstacles * points)
    throw std::runtime_error(file.string() + ": the restart and the scene differ in obstacles or points");
  std::vector<std::vector<double>> rows;
  for (std::size_t o = 0; o < obstacles; ++o)
    rows.emplace_back(table.begin() + o * points, table.begin() + (o + 1) * points);
  return rows;
}

void write_contents(const h5::Object& root, const Solver& solver, const RunRecord& run) {
  h5::write_attribute(root, "format", std::string(kFormat));
  h5::write_attribute(root, "time", solver.time());
  h5::write_attribute(root, "kinetic_energy_peak", run.kinetic_energy_peak);
  h5::write_attribute(root, "kinetic_energy_peak_since", run.kinetic_energy_peak_since);
  h5::write_attribute(root, "steps", static_cast<std::int64_t>(solver.steps()));
  h5::write_attribute(root, "drive_integral", solver.drive_integral());
  std::vector<double> rows;
  for (const MaterialPoint& mp : solver.points()) append_row(rows, mp);
  h5::write_array(root, "points", rows, kColumns);
  write_obstacle_table(root, "obstacle_tangential", solver, &Obstacle::tangential_history, 0.0);
  write_obstacle_table(root, "obstacle_held", solver, &Obstacle::held_forces, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < solver.law_count(); ++k) {
    LawEntries entries(root, k);
    solver.law(k).save_state(entries);
  }
}

}  // namespace

void write_restart(const std::filesystem::path& file, const Solver& solver, const RunRecord& run) {
  // Written aside and renamed at the end: an existing restart file (perhaps the one this run
  // started from) is replaced only by a complete one.
  std::filesystem::path partial = file;
  partial += ".partial";
  std::filesystem::remove(partial);
  {
    const h5::Object root = h5::create_file(partial);
    write_contents(root, solver, run);
    h5::flush(root);
  }
  std::filesystem::rename(partial, file);
}

RunRecord read_restart(const std::filesystem::path& file, Solver& solver) {
  const h5::Object root = h5::open_file(file, false);
  std::string format = "grainbank-restart-1";  // files of version 1 had no format attribute
  try {
    format = h5::read_string_attribute(root, "format");
  } catch (const db::StoreError&) {
  }
  if (format != kFormat)
    throw std::runtime_error(file.string() + ": restart format \"" + format + "\", expected \"" + kFormat +
                             "\": written by another grainbank version; rerun from the start");
  const std::vector<double> rows = h5::read_array<double>(root, "points", kColumns);
  std::vector<MaterialPoint> points;
  for (std::size_t k = 0; k < rows.size() / kColumns; ++k) {
    points.push_back(point_from_row(&rows[k * kColumns]));
    if (points.back().law >= solver.law_count())
      throw std::runtime_error(file.string() + ": point " + std::to_string(points.back().id) +
                               " refers to a law the scene does not have");
  }
  const std::size_t obstacles = solver.obstacles().size();
  std::vector<std::vector<double>> tangential =
      read_obstacle_table(root, "obstacle_tangential", file, obstacles, points.size());
  for (std::size_t o = 0; o < obstacles; ++o) solver.obstacle(o).set_tangential_history(std::move(tangential[o]));
  // Restarts written before gates could be let go of gradually hold none.
  if (h5::has_child(root, "obstacle_held")) {
    std::vector<std::vector<double>> held = read_obstacle_table(root, "obstacle_held", file, obstacles, points.size());
    for (std::size_t o = 0; o < obstacles; ++o)
      if (solver.obstacle(o).release().gradual()) solver.obstacle(o).set_held_forces(std::move(held[o]));
  }
  for (std::size_t k = 0; k < solver.law_count(); ++k) {
    LawEntries entries(root, k);
    solver.law(k).restore_state(entries);
  }
  try {
    solver.restore(h5::read_double_attribute(root, "time"), h5::read_int_attribute(root, "steps"), std::move(points));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
  try {
    solver.restore_drive_integral(h5::read_double_attribute(root, "drive_integral"));
  } catch (const db::StoreError&) {  // a file of an older build, whose drives held no servo
  }
  RunRecord run;
  try {
    run.kinetic_energy_peak = h5::read_double_attribute(root, "kinetic_energy_peak");
  } catch (const db::StoreError&) {  // a file of an older build: the resumed run's peak starts afresh
    run.kinetic_energy_peak_since = solver.time();
    return run;
  }
  try {
    run.kinetic_energy_peak_since = h5::read_double_attribute(root, "kinetic_energy_peak_since");
  } catch (const db::StoreError&) {  // written by a build that counted every peak from the start
  }
  return run;
}

}  // namespace grainbank::mpm::io
