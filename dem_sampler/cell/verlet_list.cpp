#include "dem_sampler/cell/verlet_list.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "dem_sampler/cell/periodic_cell.hpp"

namespace grainbank::dem {

void VerletListBuilder::build(const Mat3& h, const std::vector<Vec3>& s, const std::vector<double>& radius,
                              double max_radius, double skin, std::vector<Pair>& pairs) {
  const double cutoff = 2 * max_radius + skin;
  const Vec3 width = perpendicular_widths(h);
  if (width.minCoeff() < 2 * cutoff) {
    std::ostringstream msg;
    msg << "periodic cell too thin: smallest width " << width.minCoeff() << " m is below twice the interaction range "
        << cutoff << " m (largest diameter + Verlet skin), so a sphere would meet two images of a neighbour. "
        << "Use a cell with more spheres, a smaller deformation increment, a smaller skin, or re-tiling with a larger "
           "cap on spheres per cell.";
    throw CellTooThinError(msg.str());
  }
  Eigen::Vector3i bins;
  for (int a = 0; a < 3; ++a) bins[a] = std::max(2, static_cast<int>(std::floor(width[a] / cutoff)));
  const std::size_t n = s.size();
  // A cell stretched far beyond its packing (grains flying apart) would need bins by the million,
  // allocated and cleared at every rebuild; wider bins still hold every pair in neighbouring bins.
  const std::size_t max_bins = std::max<std::size_t>(27, 2 * n);
  while (static_cast<std::size_t>(bins.prod()) > max_bins) {
    int widest = 0;
    bins.maxCoeff(&widest);
    bins[widest] = std::max(2, bins[widest] / 2);
  }
  const std::size_t nbins = static_cast<std::size_t>(bins.prod());

  auto bin_coord = [&](const Vec3& si) {
    Eigen::Vector3i b;
    for (int a = 0; a < 3; ++a) b[a] = std::min(bins[a] - 1, static_cast<int>(si[a] * bins[a]));
    return b;
  };
  auto bin_index = [&](const Eigen::Vector3i& b) { return b[0] + bins[0] * (b[1] + bins[1] * b[2]); };

  // Counting sort of the spheres by bin.
  bin_start_.assign(nbins + 1, 0);
  std::vector<std::uint32_t> bin_of(n);
  for (std::size_t i = 0; i < n; ++i) {
    bin_of[i] = static_cast<std::uint32_t>(bin_index(bin_coord(s[i])));
    ++bin_start_[bin_of[i] + 1];
  }
  for (std::size_t b = 0; b < nbins; ++b) bin_start_[b + 1] += bin_start_[b];
  sorted_.resize(n);
  {
    std::vector<std::uint32_t> fill(bin_start_.begin(), bin_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) sorted_[fill[bin_of[i]]++] = static_cast<std::uint32_t>(i);
  }

  pairs.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::size_t first = pairs.size();
    const Eigen::Vector3i bi = bin_coord(s[i]);
    for (int code = 0; code < kShiftCount; ++code) {
      const Eigen::Vector3i d = shift_vector(code);
      Eigen::Vector3i bj = bi + d, image = Eigen::Vector3i::Zero();
      for (int a = 0; a < 3; ++a) {
        if (bj[a] < 0) { bj[a] += bins[a]; image[a] = -1; }
        else if (bj[a] >= bins[a]) { bj[a] -= bins[a]; image[a] = 1; }
      }
      const int b = bin_index(bj);
      for (std::uint32_t k = bin_start_[b]; k < bin_start_[b + 1]; ++k) {
        const std::uint32_t j = sorted_[k];
        if (j <= i) continue;
        const Vec3 l = h * (s[j] + image.cast<double>() - s[i]);
        const double range = radius[i] + radius[j] + skin;
        if (l.squaredNorm() >= range * range) continue;
        Pair p;
        p.i = i;
        p.j = j;
        p.image = static_cast<std::uint32_t>(shift_code(image));
        pairs.push_back(p);
      }
    }
    std::sort(pairs.begin() + static_cast<std::ptrdiff_t>(first), pairs.end(),
              [](const Pair& a, const Pair& b) { return a.j < b.j; });
  }
}

}  // namespace grainbank::dem
