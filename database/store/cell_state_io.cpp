#include "database/store/cell_state_io.hpp"

#include <string>

namespace grainbank::db {
namespace {

constexpr const char* kFormat = "grainbank-cell-state-1";

// Matrices are written in C order so h5py/h5dump show h[i][j] = h(i, j).
std::vector<double> matrix_values(const dem::Mat3& m) {
  std::vector<double> v;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v.push_back(m(i, j));
  return v;
}

dem::Mat3 read_matrix(const h5::Object& group, const std::string& name) {
  const std::vector<double> v = h5::read_array<double>(group, name, 3);
  if (v.size() != 9) throw StoreError(group.file(), group.name() + "/" + name + ": expected a 3 x 3 matrix");
  dem::Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = v[3 * i + j];
  return m;
}

std::vector<double> vector_values(const std::vector<dem::Vec3>& vs) {
  std::vector<double> v;
  v.reserve(3 * vs.size());
  for (const dem::Vec3& x : vs) v.insert(v.end(), x.data(), x.data() + 3);
  return v;
}

std::vector<dem::Vec3> read_vectors(const h5::Object& group, const std::string& name) {
  const std::vector<double> v = h5::read_array<double>(group, name, 3);
  std::vector<dem::Vec3> out(v.size() / 3);
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = dem::Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
  return out;
}

void require_length(const h5::Object& group, const char* name, std::size_t found, std::size_t expected) {
  if (found != expected)
    throw StoreError(group.file(), group.name() + "/" + name + ": " + std::to_string(found) + " entries, expected " +
                                       std::to_string(expected) + " (truncated or inconsistent cell state)");
}

}  // namespace

void write_cell_state(const h5::Object& group, const StoredCell& cell) {
  const dem::CellState& st = cell.state;
  h5::write_attribute(group, "format", std::string(kFormat));
  h5::write_attribute(group, "skin", cell.skin);
  h5::write_attribute(group, "time", st.time);
  h5::write_attribute(group, "initial_bond_count", st.initial_bond_count);
  h5::write_attribute(group, "last_active_pairs", st.last_active_pairs);
  h5::write_attribute(group, "last_pair_force_sum", st.last_pair_force_sum);
  h5::write_attribute(group, "spheres", static_cast<std::int64_t>(st.radius.size()));
  h5::write_attribute(group, "pairs", static_cast<std::int64_t>(st.pairs.size()));

  h5::write_array(group, "h", matrix_values(st.h), 3);
  h5::write_array(group, "h_reference", matrix_values(st.h_reference), 3);
  h5::write_array(group, "h_at_list_build", matrix_values(st.h_at_list_build), 3);
  h5::write_array(group, "last_stress", matrix_values(st.last_stress), 3);
  h5::write_array(group, "radius", st.radius, 0);
  h5::write_array(group, "reduced_position", vector_values(st.reduced_position), 3);
  h5::write_array(group, "velocity", vector_values(st.velocity), 3);
  h5::write_array(group, "angular_velocity", vector_values(st.angular_velocity), 3);
  h5::write_array(group, "force", vector_values(st.force), 3);
  h5::write_array(group, "torque", vector_values(st.torque), 3);
  h5::write_array(group, "reduced_position_at_list_build", vector_values(st.reduced_position_at_list_build), 3);

  std::vector<std::uint32_t> pi, pj, image;
  std::vector<double> damping;
  std::vector<dem::Vec3> ft;
  for (const dem::Pair& p : st.pairs) {
    pi.push_back(p.i);
    pj.push_back(p.j);
    image.push_back(p.image);
    damping.push_back(p.damping);
    ft.push_back(p.ft);
  }
  h5::write_array(group, "pair_i", pi, 0);
  h5::write_array(group, "pair_j", pj, 0);
  h5::write_array(group, "pair_image", image, 0);
  h5::write_array(group, "pair_damping", damping, 0);
  h5::write_array(group, "pair_ft", vector_values(ft), 3);

  std::vector<dem::Vec3> shear;
  std::vector<double> rest_gap;
  std::vector<std::uint8_t> intact;
  std::vector<double> integrity;
  bool softened = false;
  for (const dem::Bond& b : st.bonds) {
    shear.push_back(b.shear_displacement);
    rest_gap.push_back(b.rest_gap);
    intact.push_back(b.intact() ? 1 : 0);
    integrity.push_back(b.integrity);
    softened = softened || (b.integrity > 0 && b.integrity < 1);
  }
  h5::write_array(group, "bond_shear_displacement", vector_values(shear), 3);
  h5::write_array(group, "bond_rest_gap", rest_gap, 0);
  h5::write_array(group, "bond_intact", intact, 0);
  // Only a softening bond is neither 0 nor 1: a brittle cell's state is written as before.
  if (softened) h5::write_array(group, "bond_integrity", integrity, 0);
  h5::write_array(group, "rolling_moment", vector_values(st.rolling_moment), 3);
}

StoredCell read_cell_state(const h5::Object& group) {
  const std::string format = h5::read_string_attribute(group, "format");
  if (format != kFormat)
    throw StoreError(group.file(), group.name() + ": cell state format \"" + format + "\", expected \"" + kFormat + "\"");
  StoredCell cell;
  dem::CellState& st = cell.state;
  cell.skin = h5::read_double_attribute(group, "skin");
  st.time = h5::read_double_attribute(group, "time");
  st.initial_bond_count = h5::read_int_attribute(group, "initial_bond_count");
  st.last_active_pairs = h5::read_int_attribute(group, "last_active_pairs");
  st.last_pair_force_sum = h5::read_double_attribute(group, "last_pair_force_sum");
  const auto spheres = static_cast<std::size_t>(h5::read_int_attribute(group, "spheres"));
  const auto pairs = static_cast<std::size_t>(h5::read_int_attribute(group, "pairs"));

  st.h = read_matrix(group, "h");
  st.h_reference = read_matrix(group, "h_reference");
  st.h_at_list_build = read_matrix(group, "h_at_list_build");
  st.last_stress = read_matrix(group, "last_stress");
  st.radius = h5::read_array<double>(group, "radius", 0);
  require_length(group, "radius", st.radius.size(), spheres);
  const auto per_sphere = [&](const char* name, std::vector<dem::Vec3>& field) {
    field = read_vectors(group, name);
    require_length(group, name, field.size(), spheres);
  };
  per_sphere("reduced_position", st.reduced_position);
  per_sphere("velocity", st.velocity);
  per_sphere("angular_velocity", st.angular_velocity);
  // A fresh (never stepped) state has no forces nor list bookkeeping yet.
  st.force = read_vectors(group, "force");
  st.torque = read_vectors(group, "torque");
  st.reduced_position_at_list_build = read_vectors(group, "reduced_position_at_list_build");
  for (const auto& [name, size] : {std::pair{"force", st.force.size()}, std::pair{"torque", st.torque.size()},
                                   std::pair{"reduced_position_at_list_build", st.reduced_position_at_list_build.size()}})
    if (size != 0) require_length(group, name, size, spheres);

  const auto pi = h5::read_array<std::uint32_t>(group, "pair_i", 0);
  const auto pj = h5::read_array<std::uint32_t>(group, "pair_j", 0);
  const auto image = h5::read_array<std::uint32_t>(group, "pair_image", 0);
  const auto damping = h5::read_array<double>(group, "pair_damping", 0);
  const auto ft = read_vectors(group, "pair_ft");
  for (const auto& [name, size] : {std::pair{"pair_i", pi.size()}, std::pair{"pair_j", pj.size()},
                                   std::pair{"pair_image", image.size()}, std::pair{"pair_damping", damping.size()},
                                   std::pair{"pair_ft", ft.size()}})
    require_length(group, name, size, pairs);
  st.pairs.resize(pairs);
  for (std::size_t k = 0; k < pairs; ++k) st.pairs[k] = dem::Pair{pi[k], pj[k], image[k], damping[k], ft[k]};

  const auto shear = read_vectors(group, "bond_shear_displacement");
  const auto rest_gap = h5::read_array<double>(group, "bond_rest_gap", 0);
  const auto intact = h5::read_array<std::uint8_t>(group, "bond_intact", 0);
  require_length(group, "bond_rest_gap", rest_gap.size(), shear.size());
  require_length(group, "bond_intact", intact.size(), shear.size());
  if (!shear.empty()) require_length(group, "bond_shear_displacement", shear.size(), pairs);
  std::vector<double> integrity(intact.begin(), intact.end());
  if (h5::has_child(group, "bond_integrity")) {
    integrity = h5::read_array<double>(group, "bond_integrity", 0);
    require_length(group, "bond_integrity", integrity.size(), shear.size());
  }
  st.bonds.resize(shear.size());
  for (std::size_t k = 0; k < shear.size(); ++k) st.bonds[k] = dem::Bond{shear[k], rest_gap[k], integrity[k]};

  st.rolling_moment = read_vectors(group, "rolling_moment");
  if (!st.rolling_moment.empty()) require_length(group, "rolling_moment", st.rolling_moment.size(), pairs);
  return cell;
}

}  // namespace grainbank::db
