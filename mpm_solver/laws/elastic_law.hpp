// Linear isotropic elasticity in plane strain, written in rate form (hypo-elastic, Jaumann rate):
// σ ← R σ Rᵀ + λ tr(dε) I + 2G dε with dε = sym(L) dt, dε_zz = 0 and R = exp(skew(L) dt). The
// rotation keeps the stress of a rigidly rotating body turning with it, unchanged in magnitude; for
// small strains this is Hooke's law.
#pragma once
#include <vector>

#include "mpm_solver/core/constitutive_law.hpp"

namespace grainbank::common {
class JsonNode;
}

namespace grainbank::mpm {

struct Elasticity {
  double young = 0;    // E [Pa] > 0
  double poisson = 0;  // ν in (-1, 0.5)
  double shear_modulus() const { return young / (2 * (1 + poisson)); }
  double lame_lambda() const { return young * poisson / ((1 + poisson) * (1 - 2 * poisson)); }
  double p_wave_modulus() const { return lame_lambda() + 2 * shear_modulus(); }
  double bulk_modulus() const { return lame_lambda() + 2 * shear_modulus() / 3; }
};

// Throws std::invalid_argument naming the offending parameter.
void check(const Elasticity& e);
// "young" and "poisson" of a material object (shared with the plastic laws' readers).
Elasticity read_elasticity(const common::JsonNode& material);

// The elastic trial stress after the increment F_inc (shared with the plastic laws).
PointStress elastic_predictor(const Elasticity& e, const PointStress& stress, const KinematicIncrement& increment);

class ElasticLaw : public ConstitutiveLaw {
 public:
  ElasticLaw(double density, Elasticity elasticity);

  std::string name() const override { return "elastic"; }
  double density() const override { return density_; }
  std::size_t add_point(PointStress& initial_stress) override;
  void update(std::size_t slot, const KinematicIncrement& increment, const Mat2& F, PointStress& stress) override;
  double p_wave_modulus(std::size_t) const override { return elasticity_.p_wave_modulus(); }
  bool replicable() const override { return true; }

 private:
  double density_;
  Elasticity elasticity_;
  std::size_t points_ = 0;
};

}  // namespace grainbank::mpm
