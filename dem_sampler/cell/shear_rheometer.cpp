#include "dem_sampler/cell/shear_rheometer.hpp"

#include "dem_sampler/cell/stress_servo.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace grainbank::dem {
namespace {

void check(const RheometerSettings& s, const Material& material) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("rheometer: " + what); };
  if (!(s.inertial_number > 0) || !std::isfinite(s.inertial_number)) fail("inertial_number: expected a positive number");
  if (!(s.normal_stress > 0) || !std::isfinite(s.normal_stress)) fail("normal_stress: expected a positive stress [Pa]");
  if (!(s.strain > 0) || !std::isfinite(s.strain)) fail("strain: expected a positive number");
  if (!(s.steady_from >= 0 && s.steady_from < s.strain)) fail("steady_from: expected a strain in [0, strain)");
  require_stable_time_step_factor(s.q_t, material.contact.restitution, "rheometer: q_t");
}

// Sums over one block of the steady part.
struct Block {
  double shear = 0, normal = 0, solid_fraction = 0, coordination = 0;
  long steps = 0, samples = 0;
};

}  // namespace

RheometerResult shear_at_inertial_number(DemCell& cell, const RheometerSettings& s) {
  check(s, cell.material());
  const std::vector<double>& r = cell.radii();
  const double diameter = 2 * std::accumulate(r.begin(), r.end(), 0.0) / static_cast<double>(r.size());
  const double rate = s.inertial_number * std::sqrt(s.normal_stress / cell.material().density) / diameter;
  const double dt = cell.time_step(s.q_t);

  // Consolidated to the isotropic stress −P first, as a shear cell is loaded before it is sheared: a
  // cell prepared at another pressure would otherwise be compacted or dilated by the shear itself,
  // and its peak would measure that. Quasi-static (I = 1e-3), to 5 % of P.
  StressServoSettings consolidation;
  consolidation.tolerance = 0.05 * s.normal_stress;
  consolidation.stress_scale = s.normal_stress;
  consolidation.max_rate = 1e-3 * std::sqrt(s.normal_stress / cell.material().density) / diameter;
  consolidation.dt = dt;
  consolidation.max_steps = 400000;
  const StressServoResult consolidated = servo_to_stress(cell, -s.normal_stress * Mat3::Identity(), consolidation);
  if (!consolidated.converged) {
    std::ostringstream msg;
    msg << "rheometer: the cell could not be consolidated to P = " << s.normal_stress << " Pa (residual "
        << consolidated.residual << " Pa after " << consolidated.steps << " steps); choose a P it can carry";
    throw std::runtime_error(msg.str());
  }
  const double consolidated_solid_fraction = cell.measures().solid_fraction;

  // The normal stress is servoed on its running mean over a strain of kFilterStrain: the instantaneous
  // stress of a small rapidly sheared cell is a train of collisions, and a servo chasing it rectifies
  // them into a mean above P. A 10 % error of the mean then dilates or compacts the cell as fast as
  // it shears, and never faster.
  constexpr double kFilterStrain = 0.02;
  constexpr double kPeakStrain = 0.005;  // short enough to resolve a peak reached at γ ≈ 0.01–0.05
  Mat3 L = Mat3::Zero();
  L(0, 1) = rate;
  double filtered_normal = cell.stress()(1, 1);
  const long steps = static_cast<long>(std::ceil(s.strain / (rate * dt)));
  const long first_steady = static_cast<long>(std::ceil(s.steady_from / (rate * dt)));
  constexpr int kBlocks = 10;
  constexpr long kMeasureEvery = 20;  // solid fraction and coordination: a sum over spheres
  std::vector<Block> blocks(kBlocks);
  const double filter = std::min(1.0, rate * dt / kFilterStrain);
  const double peak_filter = std::min(1.0, rate * dt / kPeakStrain);
  double filtered_shear = 0, peak_shear = -std::numeric_limits<double>::infinity(), peak_strain = 0;
  for (long step = 0; step < steps; ++step) {
    L(1, 1) = std::clamp(rate * (-s.normal_stress - filtered_normal) / (0.1 * s.normal_stress), -rate, rate);
    cell.step_with_velocity_gradient(L, dt);
    filtered_normal += filter * (cell.stress()(1, 1) - filtered_normal);
    const Mat3& sigma = cell.stress();
    filtered_shear += peak_filter * (0.5 * (sigma(0, 1) + sigma(1, 0)) - filtered_shear);
    // Not before the filter has seen a strain of kPeakStrain: it starts from zero.
    if (static_cast<double>(step) * rate * dt >= kPeakStrain && filtered_shear > peak_shear)
      peak_shear = filtered_shear, peak_strain = static_cast<double>(step + 1) * rate * dt;
    if (step < first_steady) continue;
    Block& b = blocks[static_cast<std::size_t>(kBlocks * (step - first_steady) / (steps - first_steady))];
    if (!sigma.allFinite()) {
      std::ostringstream msg;
      msg << "rheometer: the stress became non-finite at γ = " << rate * dt * static_cast<double>(step)
          << "; lower q_t";
      throw std::runtime_error(msg.str());
    }
    b.shear += 0.5 * (sigma(0, 1) + sigma(1, 0));
    b.normal -= sigma(1, 1);
    ++b.steps;
    if (step % kMeasureEvery == 0) {
      const CellMeasures m = cell.measures();
      b.solid_fraction += m.solid_fraction;
      b.coordination += m.coordination;
      ++b.samples;
    }
  }

  RheometerResult out;
  out.inertial_number = s.inertial_number;
  out.shear_rate = rate;
  out.steps = steps;
  out.peak_shear = peak_shear, out.peak_strain = peak_strain;
  out.consolidation_steps = consolidated.steps;
  out.consolidated_solid_fraction = consolidated_solid_fraction;
  Block total;
  std::vector<double> block_friction;
  for (const Block& b : blocks) {
    if (b.steps == 0) continue;
    total.shear += b.shear, total.normal += b.normal, total.steps += b.steps;
    total.solid_fraction += b.solid_fraction, total.coordination += b.coordination, total.samples += b.samples;
    block_friction.push_back(b.shear / b.normal);
  }
  out.friction = total.shear / total.normal;
  out.normal_stress = total.normal / static_cast<double>(total.steps);
  out.solid_fraction = total.samples ? total.solid_fraction / static_cast<double>(total.samples) : 0;
  out.coordination = total.samples ? total.coordination / static_cast<double>(total.samples) : 0;
  const double n = static_cast<double>(block_friction.size());
  if (n > 1) {
    const double mean = std::accumulate(block_friction.begin(), block_friction.end(), 0.0) / n;
    double square = 0;
    for (double m : block_friction) square += (m - mean) * (m - mean);
    out.friction_error = std::sqrt(square / (n - 1) / n);
  }
  return out;
}

}  // namespace grainbank::dem
