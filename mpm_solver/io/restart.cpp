#include "restart.hpp"

#include <map>
#include <stdexcept>
#include <string>

#include "core/live_dem_law.hpp"
#include "coupling/library_law.hpp"
#include "store/cell_state_io.hpp"
#include "store/hdf5_handle.hpp"

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

std::string cell_group(std::size_t law, std::size_t slot) {
  return "law_" + std::to_string(law) + "_cell_" + std::to_string(slot);
}

// Per point of a cache/hybrid law: slot, damage, live (0/1), steps inside the tolerance; live cells
// as cell groups; the replay histories as rows slot, F_inc (4), L (4), dt, in step order.
constexpr hsize_t kLibraryColumns = 4;
constexpr hsize_t kHistoryColumns = 10;
std::string library_points(std::size_t law) { return "law_" + std::to_string(law) + "_library_points"; }
std::string replay_history(std::size_t law) { return "law_" + std::to_string(law) + "_replay_history"; }

void write_contents(const h5::Object& root, const Solver& solver) {
  h5::write_attribute(root, "format", std::string(kFormat));
  h5::write_attribute(root, "time", solver.time());
  h5::write_attribute(root, "steps", static_cast<std::int64_t>(solver.steps()));
  std::vector<double> rows;
  for (const MaterialPoint& mp : solver.points()) append_row(rows, mp);
  h5::write_array(root, "points", rows, kColumns);
  std::vector<double> tangential;
  for (const Obstacle& o : solver.obstacles()) {
    std::vector<double> history = o.tangential_history();
    history.resize(solver.points().size(), 0.0);
    tangential.insert(tangential.end(), history.begin(), history.end());
  }
  h5::write_array(root, "obstacle_tangential", tangential, solver.points().size());
  for (const MaterialPoint& mp : solver.points())
    if (const auto* live = dynamic_cast<const LiveDemLaw*>(&solver.law(mp.law))) {
      const dem::DemCell& cell = live->cell(mp.slot);
      db::write_cell_state(h5::create_group(root, cell_group(mp.law, mp.slot)), db::StoredCell{cell.state(), cell.skin()});
    }
  for (std::size_t k = 0; k < solver.law_count(); ++k) {
    const auto* law = dynamic_cast<const LibraryLaw*>(&solver.law(k));
    if (!law) continue;
    std::vector<double> rows, history;
    for (const MaterialPoint& mp : solver.points()) {
      if (mp.law != k) continue;
      const LibraryLaw::CarriedState state = law->carried_state(mp.slot);
      const dem::DemCell* cell = law->live_cell(mp.slot);
      rows.insert(rows.end(), {double(mp.slot), state.damage, cell ? 1.0 : 0.0, double(state.steps_inside)});
      for (const KinematicIncrement& r : state.history)
        history.insert(history.end(), {double(mp.slot), r.F(0, 0), r.F(0, 1), r.F(1, 0), r.F(1, 1), r.L(0, 0), r.L(0, 1),
                                       r.L(1, 0), r.L(1, 1), r.dt});
      if (cell)
        db::write_cell_state(h5::create_group(root, cell_group(k, mp.slot)), db::StoredCell{cell->state(), cell->skin()});
    }
    h5::write_array(root, library_points(k), rows, kLibraryColumns);
    h5::write_array(root, replay_history(k), history, kHistoryColumns);
  }
}

}  // namespace

void write_restart(const std::filesystem::path& file, const Solver& solver) {
  // Written aside and renamed at the end: an existing restart file (perhaps the one this run
  // started from) is replaced only by a complete one.
  std::filesystem::path partial = file;
  partial += ".partial";
  std::filesystem::remove(partial);
  {
    const h5::Object root = h5::create_file(partial);
    write_contents(root, solver);
    h5::flush(root);
  }
  std::filesystem::rename(partial, file);
}

void read_restart(const std::filesystem::path& file, Solver& solver) {
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
  const std::vector<double> tangential = h5::read_array<double>(root, "obstacle_tangential", points.size());
  if (tangential.size() != solver.obstacles().size() * points.size())
    throw std::runtime_error(file.string() + ": the restart and the scene differ in obstacles or points");
  for (std::size_t o = 0; o < solver.obstacles().size(); ++o)
    solver.obstacle(o).set_tangential_history(
        std::vector<double>(tangential.begin() + o * points.size(), tangential.begin() + (o + 1) * points.size()));
  for (const MaterialPoint& mp : points)
    if (auto* live = dynamic_cast<LiveDemLaw*>(&solver.law(mp.law)))
      live->restore_cell(mp.slot, db::read_cell_state(h5::open_group(root, cell_group(mp.law, mp.slot))).state);
  for (std::size_t k = 0; k < solver.law_count(); ++k) {
    auto* law = dynamic_cast<LibraryLaw*>(&solver.law(k));
    if (!law) continue;
    const std::vector<double> rows = h5::read_array<double>(root, library_points(k), kLibraryColumns);
    std::map<std::size_t, std::vector<KinematicIncrement>> histories;
    const std::vector<double> history = h5::read_array<double>(root, replay_history(k), kHistoryColumns);
    for (std::size_t r = 0; r < history.size(); r += kHistoryColumns) {
      KinematicIncrement increment;
      increment.F << history[r + 1], history[r + 2], history[r + 3], history[r + 4];
      increment.L << history[r + 5], history[r + 6], history[r + 7], history[r + 8];
      increment.dt = history[r + 9];
      histories[static_cast<std::size_t>(history[r])].push_back(increment);
    }
    for (std::size_t r = 0; r < rows.size(); r += kLibraryColumns) {
      const auto slot = static_cast<std::size_t>(rows[r]);
      LibraryLaw::CarriedState state;
      state.damage = rows[r + 1];
      state.steps_inside = static_cast<int>(rows[r + 3]);
      state.history = std::move(histories[slot]);
      std::optional<dem::CellState> cell;
      if (rows[r + 2] != 0) cell = db::read_cell_state(h5::open_group(root, cell_group(k, slot))).state;
      law->restore_point(slot, std::move(state), std::move(cell));
    }
  }
  try {
    solver.restore(h5::read_double_attribute(root, "time"), h5::read_int_attribute(root, "steps"), std::move(points));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
}

}  // namespace grainbank::mpm::io
