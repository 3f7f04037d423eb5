#include "mpm_solver/io/audit_trail.hpp"

#include <algorithm>
#include <stdexcept>

#include "mpm_solver/core/dem_backed_law.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "database/store/error.hpp"
#include "database/store/hdf5_handle.hpp"

namespace grainbank::mpm::io {

namespace h5 = db::h5;

AuditTrailRecorder::AuditTrailRecorder(const Solver& solver, std::vector<std::uint32_t> ids, std::string scene) {
  trail_.start_time = solver.time();
  trail_.scene = std::move(scene);
  slot_of_id_.assign(solver.points().size(), -1);
  for (const std::uint32_t id : ids) {
    if (id >= slot_of_id_.size())
      throw std::invalid_argument("audit: no material point with id " + std::to_string(id));
    slot_of_id_[id] = static_cast<std::int64_t>(trail_.points.size());
    trail_.points.push_back({id, {}});
  }
}

void AuditTrailRecorder::record(const Solver& solver, double dt) {
  // Points are re-sorted during the run: find the sampled ones by id.
  for (const MaterialPoint& mp : solver.points()) {
    const std::int64_t k = slot_of_id_[mp.id];
    if (k < 0) continue;
    trail_.points[k].steps.push_back(
        {solver.time(), dt, mp.velocity_gradient, mp.stress, stress_source(solver.law(mp.law), mp.slot)});
  }
}

namespace {

void write_trail_file(const std::filesystem::path& file, const AuditTrail& trail) {
  const h5::Object root = h5::create_file(file);
  h5::write_attribute(root, "start_time", trail.start_time);
  h5::write_attribute(root, "scene", trail.scene);
  const h5::Object points = h5::create_group(root, "points");
  for (const PointTrail& p : trail.points) {
    std::vector<double> time, dt, gradient, stress;
    std::vector<std::int64_t> source;
    for (const TrailStep& s : p.steps) {
      time.push_back(s.time), dt.push_back(s.dt);
      const Mat2& L = s.velocity_gradient;
      gradient.insert(gradient.end(), {L(0, 0), L(0, 1), L(1, 0), L(1, 1)});
      const Mat2& sigma = s.stress.in_plane;
      stress.insert(stress.end(), {sigma(0, 0), sigma(1, 1), sigma(0, 1), s.stress.zz});
      source.push_back(static_cast<std::int64_t>(s.source));
    }
    const h5::Object group = h5::create_group(points, std::to_string(p.id));
    h5::write_array(group, "time", time, 0);
    h5::write_array(group, "dt", dt, 0);
    h5::write_array(group, "velocity_gradient", gradient, 4);
    h5::write_array(group, "stress", stress, 4);
    h5::write_array(group, "source", source, 0);
  }
  h5::flush(root);
}

}  // namespace

void write_audit_trail(const std::filesystem::path& file, const AuditTrail& trail) {
  // Written beside and renamed over: a run into a folder that holds an earlier run's trail replaces
  // it, as it replaces the other outputs, and a crash mid-write leaves the old one whole.
  std::filesystem::path partial = file;
  partial += ".partial";
  std::filesystem::remove(partial);
  write_trail_file(partial, trail);
  std::filesystem::rename(partial, file);
}

AuditTrail read_audit_trail(const std::filesystem::path& file) {
  const h5::Object root = h5::open_file(file, false);
  AuditTrail trail;
  trail.start_time = h5::read_double_attribute(root, "start_time");
  trail.scene = h5::read_string_attribute(root, "scene");
  const h5::Object points = h5::open_group(root, "points");
  for (const std::string& name : h5::child_names(points)) {
    const h5::Object group = h5::open_group(points, name);
    PointTrail p;
    try {
      p.id = static_cast<std::uint32_t>(std::stoul(name));
    } catch (const std::exception&) {
      throw db::StoreError(file, "/points/" + name + ": expected a group named by a point id");
    }
    const auto time = h5::read_array<double>(group, "time", 0), dt = h5::read_array<double>(group, "dt", 0);
    const auto gradient = h5::read_array<double>(group, "velocity_gradient", 4);
    const auto stress = h5::read_array<double>(group, "stress", 4);
    const auto source = h5::read_array<std::int64_t>(group, "source", 0);
    const std::size_t n = time.size();
    if (dt.size() != n || gradient.size() != 4 * n || stress.size() != 4 * n || source.size() != n)
      throw db::StoreError(file, "/points/" + name + ": datasets of different lengths (expected " + std::to_string(n) +
                                     " steps in each)");
    for (std::size_t i = 0; i < n; ++i) {
      TrailStep s;
      s.time = time[i], s.dt = dt[i];
      s.velocity_gradient << gradient[4 * i], gradient[4 * i + 1], gradient[4 * i + 2], gradient[4 * i + 3];
      s.stress.in_plane << stress[4 * i], stress[4 * i + 2], stress[4 * i + 2], stress[4 * i + 1];
      s.stress.zz = stress[4 * i + 3];
      if (source[i] < 0 || source[i] > static_cast<std::int64_t>(StressSource::miss))
        throw db::StoreError(file, "/points/" + name + "/source: expected values 0 to 3, got " + std::to_string(source[i]));
      s.source = static_cast<StressSource>(source[i]);
      p.steps.push_back(s);
    }
    trail.points.push_back(std::move(p));
  }
  return trail;
}

std::vector<std::uint32_t> spread_audit_points(const Solver& solver, std::size_t count) {
  std::vector<std::uint32_t> dem_backed;
  for (const MaterialPoint& mp : solver.points()) {
    if (solver.law(mp.law).dem_backed()) dem_backed.push_back(mp.id);
  }
  std::sort(dem_backed.begin(), dem_backed.end());
  if (count == 0 || count > dem_backed.size())
    throw std::invalid_argument("expected 1 to " + std::to_string(dem_backed.size()) +
                                " points (the points of DEM-backed materials), got " + std::to_string(count));
  std::vector<std::uint32_t> ids;
  for (std::size_t k = 0; k < count; ++k) ids.push_back(dem_backed[(2 * k + 1) * dem_backed.size() / (2 * count)]);
  return ids;
}

}  // namespace grainbank::mpm::io
