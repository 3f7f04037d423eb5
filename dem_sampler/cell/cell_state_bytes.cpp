#include "dem_sampler/cell/cell_state_bytes.hpp"

namespace grainbank::dem {

namespace {

void put_vec3s(const std::vector<Vec3>& values, common::ByteWriter& out) {
  out.put<std::uint64_t>(values.size());
  for (const Vec3& v : values) out.put_matrix(v);
}

std::vector<Vec3> get_vec3s(common::ByteReader& in) {
  return in.get_each([&] { return in.get_matrix<Vec3>(); });
}

}  // namespace

void write_cell_state(const CellState& s, common::ByteWriter& out) {
  out.put_matrix(s.h);
  out.put_matrix(s.h_reference);
  out.put(s.time);
  out.put_vector(s.radius);
  put_vec3s(s.reduced_position, out);
  put_vec3s(s.velocity, out);
  put_vec3s(s.angular_velocity, out);
  put_vec3s(s.force, out);
  put_vec3s(s.torque, out);
  out.put<std::uint64_t>(s.pairs.size());
  for (const Pair& p : s.pairs) {
    out.put(p.i), out.put(p.j), out.put(p.image), out.put(p.damping);
    out.put_matrix(p.ft);
  }
  out.put<std::uint64_t>(s.bonds.size());
  for (const Bond& b : s.bonds) {
    out.put_matrix(b.shear_displacement);
    out.put(b.rest_gap), out.put(b.integrity);
  }
  put_vec3s(s.rolling_moment, out);
  out.put(s.initial_bond_count);
  out.put_matrix(s.h_at_list_build);
  put_vec3s(s.reduced_position_at_list_build, out);
  out.put_matrix(s.last_stress);
  out.put(s.last_active_pairs);
  out.put(s.last_pair_force_sum);
}

CellState read_cell_state(common::ByteReader& in) {
  CellState s;
  s.h = in.get_matrix<Mat3>();
  s.h_reference = in.get_matrix<Mat3>();
  s.time = in.get<double>();
  s.radius = in.get_vector<double>();
  s.reduced_position = get_vec3s(in);
  s.velocity = get_vec3s(in);
  s.angular_velocity = get_vec3s(in);
  s.force = get_vec3s(in);
  s.torque = get_vec3s(in);
  s.pairs = in.get_each([&] {
    Pair p;
    p.i = in.get<std::uint32_t>(), p.j = in.get<std::uint32_t>(), p.image = in.get<std::uint32_t>();
    p.damping = in.get<double>();
    p.ft = in.get_matrix<Vec3>();
    return p;
  });
  s.bonds = in.get_each([&] {
    Bond b;
    b.shear_displacement = in.get_matrix<Vec3>();
    b.rest_gap = in.get<double>();
    b.integrity = in.get<double>();
    return b;
  });
  s.rolling_moment = get_vec3s(in);
  s.initial_bond_count = in.get<std::int64_t>();
  s.h_at_list_build = in.get_matrix<Mat3>();
  s.reduced_position_at_list_build = get_vec3s(in);
  s.last_stress = in.get_matrix<Mat3>();
  s.last_active_pairs = in.get<std::int64_t>();
  s.last_pair_force_sum = in.get<double>();
  return s;
}

}  // namespace grainbank::dem
