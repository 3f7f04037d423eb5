#include "mpm_solver/core/solver.hpp"

#include <algorithm>
#include <cmath>
#include <chrono>
#include <exception>
#include <limits>
#include <omp.h>
#include <sstream>
#include <stdexcept>
#include <string>

#include "mpm_solver/core/parallel.hpp"

namespace grainbank::mpm {

namespace {
// Adds the wall time of f() to `total`.
template <class F>
void timed(double& total, F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The first exception thrown in an OpenMP loop over points (none may escape the parallel region),
// rethrown afterwards as a std::runtime_error prefixed with the context of the point it concerns.
class FirstFailure {
 public:
  void capture(const std::string& context, const std::exception& e) {
#pragma omp critical(mpm_first_failure)
    if (!failure_) failure_ = std::make_exception_ptr(std::runtime_error(context + e.what()));
  }
  void rethrow_if_any() const {
    if (failure_) std::rethrow_exception(failure_);
  }
  std::string message() const {
    try {
      rethrow_if_any();
    } catch (const std::exception& e) {
      return e.what();
    }
    return {};
  }

 private:
  std::exception_ptr failure_;
};

std::string at_time(double t) {
  std::ostringstream out;
  out << " at t = " << t << " s: ";
  return out.str();
}
}  // namespace

Solver::Solver(Grid grid, SolverSettings settings)
    : grid_(std::move(grid)), settings_(settings), buffers_(grid_.node_count()) {
  if (!(settings_.transfer.pic_rate >= 0)) throw std::invalid_argument("pic_rate: expected a number >= 0 [1/s]");
  if (settings_.transfer.noise_rate && !(*settings_.transfer.noise_rate >= 0))
    throw std::invalid_argument("noise_rate: expected a number >= 0 [1/s]");
  if (!(settings_.time_step.cfl > 0) || !(settings_.time_step.contact > 0))
    throw std::invalid_argument("time-step factors must be positive");
  if (!(settings_.skip_strain_increment >= 0))
    throw std::invalid_argument("skip_strain_increment: expected a number >= 0");
  if (!(settings_.max_time_step > 0)) throw std::invalid_argument("max_time_step: expected a positive number");
  if (settings_.sort_interval < 1) throw std::invalid_argument("sort_interval: expected an integer >= 1");
  if (settings_.rebalance_interval < 1) throw std::invalid_argument("rebalance_interval: expected an integer >= 1");
}

std::size_t Solver::add_law(std::unique_ptr<ConstitutiveLaw> law) {
  laws_.push_back(std::move(law));
  return laws_.size() - 1;
}

std::uint32_t Solver::add_point(std::size_t law, const Vec2& position, double volume, double radius,
                                const Vec2& velocity) {
  if (law >= laws_.size()) throw std::invalid_argument("add_point: no such law");
  if (!grid_.contains(position)) throw std::invalid_argument("add_point: the point lies outside the grid");
  if (!(volume > 0) || !(radius > 0)) throw std::invalid_argument("add_point: volume and radius must be positive");
  MaterialPoint mp;
  mp.id = static_cast<std::uint32_t>(points_.size());
  mp.law = static_cast<std::uint32_t>(law);
  mp.slot = static_cast<std::uint32_t>(laws_[law]->add_point(mp.stress));
  mp.initial_volume = mp.volume = volume;
  mp.mass = laws_[law]->density() * volume;
  mp.radius = radius;
  mp.position = position;
  mp.velocity = velocity;
  points_.push_back(mp);
  point_update_seconds_.push_back(0);
  return mp.id;
}

void Solver::restore(double time, long steps, std::vector<MaterialPoint> points) {
  if (points.size() != points_.size())
    throw std::invalid_argument("restore: the restart holds " + std::to_string(points.size()) +
                                " points, the scene " + std::to_string(points_.size()));
  time_ = time;
  steps_ = steps;
  points_ = std::move(points);
}

void Solver::add_obstacle(Obstacle obstacle) { obstacles_.push_back(std::move(obstacle)); }

void Solver::set_ranks(std::shared_ptr<const Ranks> ranks) { distribution_.set_ranks(std::move(ranks), laws_); }

void Solver::gather_point_states(const std::vector<std::uint32_t>& ids) {
  distribution_.gather_point_states(points_, laws_, ids);
}

TimeStepLimits Solver::time_step_limits() const {
  const auto replicated = [&](const MaterialPoint& mp) { return !laws_[mp.law]->point_sharing(); };
  TimeStepLimits limits = critical_time_step(grid_, points_, laws_, obstacles_, time_, settings_.time_step, replicated);
  // The own limit of a spread point (a live cell's seed Eq. 4) needs its current state: the rank
  // that updates it computes it, as part of the point's cost.
  for (const MaterialPoint& mp : points_)
    if (!replicated(mp) && distribution_.updates_here(mp, laws_))
      timed(point_update_seconds_[mp.id], [&] { limits.law = std::min(limits.law, law_limit_of(mp, laws_)); });
  if (distribution_.spread()) limits.law = distribution_.ranks().min(limits.law);
  return limits;
}

double Solver::stable_time_step() const { return std::min(time_step_limits().minimum(), settings_.max_time_step); }

const MaterialPoint& Solver::law_limiting_point() const {
  const auto here = [&](const MaterialPoint& mp) { return distribution_.updates_here(mp, laws_); };
  const std::size_t local = mpm::law_limiting_point(points_, laws_, here);
  const auto [value, id] = distribution_.min_over_ranks(
      {local < points_.size() ? law_limit_of(points_[local], laws_) : std::numeric_limits<double>::infinity(),
       local < points_.size() ? points_[local].id : UINT32_MAX});
  const auto at = std::find_if(points_.begin(), points_.end(), [id = id](const MaterialPoint& mp) { return mp.id == id; });
  return at == points_.end() ? points_.front() : *at;
}

// One MUSL step, top to bottom (seed §2.1).
void Solver::finish() {
  for (const std::unique_ptr<ConstitutiveLaw>& law : laws_) law->finish();
}

void Solver::step(double dt) {
  if (!(dt > 0)) throw std::invalid_argument("step: expected a positive time step");
  if (steps_ % settings_.sort_interval == 0) timed(phase_times_.sort, [&] { sort_points_by_cell(); });
  if (distribution_.spread() && steps_ > 0 && steps_ % settings_.rebalance_interval == 0) rebalance();
  locate_points();
  timed(phase_times_.particles_to_grid, [&] { particles_to_grid(grid_, points_, stencils_, buffers_); });
  timed(phase_times_.contact, [&] { apply_obstacle_contacts(dt); });
  std::optional<HomogeneousDrive> drive;
  if (settings_.homogeneous_drive) drive = servoed_drive(*settings_.homogeneous_drive, points_, dt, drive_integral_);
  timed(phase_times_.grid, [&] {
    update_grid(grid_, gravity_.at(time_));
    if (settings_.channel_walls) apply_channel_walls(grid_, points_, stencils_, *settings_.channel_walls, dt);
    if (drive) impose_homogeneous_velocity(grid_, *drive);
  });
  timed(phase_times_.grid_to_particles, [&] {
    grid_to_particles(grid_, points_, stencils_, dt, settings_.transfer, fluctuations_);
    if (settings_.transfer.splits_fluctuations())
      blend_in_fluctuations(grid_, points_, stencils_, fluctuations_, dt, settings_.transfer, buffers_);
    remap_velocities(grid_, points_, stencils_, buffers_);
    if (drive) impose_homogeneous_velocity(grid_, *drive);
  });
  timed(phase_times_.stress, [&] { update_stresses(dt); });
  time_ += dt;
  ++steps_;
}

void Solver::rebalance() {
  point_update_seconds_at_rebalance_.resize(point_update_seconds_.size(), 0.0);
  std::vector<double> since(point_update_seconds_.size());
  for (std::size_t id = 0; id < since.size(); ++id)
    since[id] = point_update_seconds_[id] - point_update_seconds_at_rebalance_[id];
  point_update_seconds_at_rebalance_ = point_update_seconds_;
  distribution_.rebalance(points_, laws_, since);
}

void Solver::sort_points_by_cell() {
  // Counting sort: points of one cell become neighbours in memory, and so do their nodes.
  const std::size_t cells = static_cast<std::size_t>(grid_.cells_x()) * grid_.cells_y();
  std::vector<std::size_t> start(cells + 1, 0), key(points_.size());
  for (std::size_t p = 0; p < points_.size(); ++p) {
    if (!grid_.contains(points_[p].position)) return;  // locate_points reports it
    key[p] = grid_.cell_index(points_[p].position);
    ++start[key[p] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
  std::vector<MaterialPoint> sorted(points_.size());
  for (std::size_t p = 0; p < points_.size(); ++p) sorted[start[key[p]]++] = points_[p];
  points_.swap(sorted);
}

void Solver::locate_points() {
  for (const MaterialPoint& mp : points_)
    if (!grid_.contains(mp.position) || !mp.position.allFinite()) {
      std::ostringstream msg;
      msg << "material point " << mp.id << " (law " << laws_[mp.law]->name() << ") left the grid at t = " << time_
          << " s: position (" << mp.position.x() << ", " << mp.position.y() << "), velocity (" << mp.velocity.x()
          << ", " << mp.velocity.y() << ") m/s, grid [" << grid_.lower().x() << ", " << grid_.upper().x() << "] x ["
          << grid_.lower().y() << ", " << grid_.upper().y() << "]; enlarge the grid or add walls, or, if that speed is "
          << "not physical, look at the point's law (a cache law answering misses far from its library can throw "
             "points: see misses in series.csv)";
      throw std::runtime_error(msg.str());
    }
  compute_stencils(grid_, points_, stencils_);
}

void Solver::apply_obstacle_contacts(double dt) {
  const long n = static_cast<long>(points_.size());
  for (Obstacle& o : obstacles_) o.reserve_points(points_.size());
  touching_.resize(std::max(omp_get_max_threads(), 1));
  for (std::vector<TouchingContact>& list : touching_) list.clear();
  FirstFailure failure;
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (long p = 0; p < n; ++p) {
    const MaterialPoint& mp = points_[p];
    std::vector<TouchingContact>& mine = touching_[omp_get_thread_num()];
    ContactSpread spread;
    const auto velocity_at = [&](const Vec2& touching) {
      spread = contact_spread(grid_, mp.position, (mp.position - touching).normalized(), 2 * mp.radius);
      return material_velocity(grid_, spread);
    };
    for (std::size_t k = 0; k < obstacles_.size(); ++k) {
      Obstacle& o = obstacles_[k];
      if (!o.active(time_)) continue;
      try {
        const AppliedForce applied = o.contact_force(mp.id, mp.position, velocity_at, mp.radius, mp.mass, time_, dt);
        if (!applied.force.isZero(0)) mine.push_back({applied.force, spread});
      } catch (const std::exception& e) {
        failure.capture("material point " + std::to_string(mp.id) + " (obstacle " + std::to_string(k) + ")" +
                            at_time(time_),
                        e);
      }
    }
  }
  failure.rethrow_if_any();
  // Serially, in the points' order (a static schedule hands each thread one run of points, in order):
  // the nodal sums come out the same whatever the threads.
  for (const std::vector<TouchingContact>& list : touching_)
    for (const TouchingContact& contact : list) add_contact_force(grid_, contact.spread, contact.force);
}

void Solver::update_stresses(double dt) {
  const long n = static_cast<long>(points_.size());
  // Live DEM points cost milliseconds each and unevenly: hand them out one at a time. Cheap updates
  // of few points run serially: waking threads would cost more than the work (on a busy machine,
  // a scheduler quantum per step).
  const bool any_expensive_law =
      std::any_of(laws_.begin(), laws_.end(), [](const auto& law) { return law->expensive(); });
  const int chunk = any_expensive_law ? 1 : 256;
  const double skip = settings_.skip_strain_increment;
  long skipped = 0;
  // Which points skipped their call, for the ranks that did not update them (point_distribution.hpp).
  std::vector<char> skipped_point(distribution_.spread() ? points_.size() : 0);
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (long p = 0; p < n; ++p) points_[p].velocity_gradient = velocity_gradient(grid_, stencils_[p]);
  if (settings_.regularization) settings_.regularization->apply(points_);
  FirstFailure failure;
#pragma omp parallel for schedule(dynamic, chunk) reduction(+ : skipped) if (any_expensive_law || n >= kMinParallelItems)
  for (long p = 0; p < n; ++p) {
    MaterialPoint& mp = points_[p];
    try {
      ConstitutiveLaw& law = *laws_[mp.law];
      const KinematicIncrement step = KinematicIncrement::of_velocity_gradient(mp.velocity_gradient, dt);
      mp.deformation_gradient = step.F * mp.deformation_gradient;
      if (!distribution_.updates_here(mp, laws_)) continue;  // its owner sends the rest
      // Only a law whose points may be shared needs its points' cost (point_distribution.hpp); a clock
      // read per point is a tenth of an analytic law's step.
      const bool timed_point = law.point_sharing() != nullptr;
      const auto owner_start = timed_point ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
      const Mat2 pending = step.F * mp.pending_increment;
      const Mat2 pending_motion = pending - Mat2::Identity();
      const double pending_time = mp.pending_time + dt;
      if (skip > 0 && pending_motion.norm() < skip &&
          law.time_step_limit(mp.slot, mp.deformation_gradient, pending_motion / pending_time) >= pending_time) {
        // Rotation counts in the criterion and the stress is held: a law receives every rotation
        // once, in its own objective update, and a cell never moves faster than seed Eq. 4 allows.
        mp.pending_increment = pending;
        mp.pending_time = pending_time;
        ++skipped;
        if (!skipped_point.empty()) skipped_point[p] = 1;
      } else {
        const KinematicIncrement increment =
            mp.pending_time == 0 ? step : KinematicIncrement::of_deformation(pending, pending_time);
        law.update(mp.slot, increment, mp.deformation_gradient, mp.stress);
        mp.pending_increment.setIdentity();
        mp.pending_time = 0;
      }
      // The volume follows the motion, step by step, not det F: at a front a lone point's F can be
      // sheared to |F| ~ 1e8, where det F is round-off and may turn negative, and a negative volume
      // turns the point's internal force around (stop 73: such a point blew up, 70 m/s in 1 ms).
      mp.volume = mp.initial_volume *
                  law.volume_ratio(mp.slot, mp.volume / mp.initial_volume * std::exp(step.L.trace() * dt));
      if (timed_point)
        point_update_seconds_[mp.id] +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - owner_start).count();
    } catch (const std::exception& e) {
      failure.capture("material point " + std::to_string(mp.id) + " (law " + laws_[mp.law]->name() + ")" + at_time(time_),
                      e);
    }
  }
  if (distribution_.spread()) {
    share_failure(distribution_.ranks(), failure.message());
    skipped += distribution_.share_updates(points_, laws_, skipped_point);
  }
  failure.rethrow_if_any();
  for (const std::unique_ptr<ConstitutiveLaw>& law : laws_) law->end_step();
  skipped_updates_ += skipped;
  point_updates_ += n;
}

}  // namespace grainbank::mpm
