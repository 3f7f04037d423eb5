#include "mpm_solver/io/vtu_writer.hpp"

#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "mpm_solver/core/dem_backed_law.hpp"
#include "mpm_solver/core/material_point.hpp"

namespace grainbank::mpm::io {

namespace {

// The arrays of one VTU file: XML headers with offsets into the appended block, then the block.
class AppendedArrays {
 public:
  template <class T>
  void add(const std::string& name, const std::string& type, int components, const std::vector<T>& values) {
    xml_ << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\"" << components
         << "\" format=\"appended\" offset=\"" << data_.size() << "\"/>\n";
    const std::uint64_t bytes = values.size() * sizeof(T);
    data_.append(reinterpret_cast<const char*>(&bytes), sizeof bytes);
    data_.append(reinterpret_cast<const char*>(values.data()), bytes);
  }
  std::string take_xml() {
    std::string s = xml_.str();
    xml_.str("");
    return s;
  }
  const std::string& data() const { return data_; }

 private:
  std::ostringstream xml_;
  std::string data_;
};

}  // namespace

void write_vtu(const std::filesystem::path& file, const Solver& solver) {
  const auto& points = solver.points();
  const std::size_t n = points.size();
  std::vector<double> xyz, velocity, stress, pressure, q, rate, damage, density, error;
  std::vector<std::int32_t> law, source;
  std::vector<std::int64_t> hits, misses, live_steps, retilings, regenerations, dispersed_holds;
  std::vector<std::int64_t> id, connectivity, offsets;
  std::vector<std::uint8_t> types(n, 1);  // VTK_VERTEX
  for (std::size_t k = 0; k < n; ++k) {
    const MaterialPoint& mp = points[k];
    xyz.insert(xyz.end(), {mp.position.x(), mp.position.y(), 0.0});
    velocity.insert(velocity.end(), {mp.velocity.x(), mp.velocity.y(), 0.0});
    const Mat2& s = mp.stress.in_plane;
    stress.insert(stress.end(), {s(0, 0), s(0, 1), 0.0, s(1, 0), s(1, 1), 0.0, 0.0, 0.0, mp.stress.zz});
    pressure.push_back(pressure_of(mp.stress));
    q.push_back(deviatoric_stress_of(mp.stress));
    rate.push_back(deviatoric_strain_rate(mp.velocity_gradient));
    damage.push_back(solver.law(mp.law).damage(mp.slot));
    density.push_back(mp.mass / mp.volume);
    law.push_back(static_cast<std::int32_t>(mp.law));
    const DemBackedLaw* dem = solver.law(mp.law).dem_backed();
    source.push_back(static_cast<std::int32_t>(stress_source(solver.law(mp.law), mp.slot)));
    error.push_back(dem ? dem->estimated_error(mp.slot) : 0.0);
    const CouplingCounters c = dem ? dem->point_counters(mp.slot) : CouplingCounters{};
    hits.push_back(static_cast<std::int64_t>(c.hits));
    misses.push_back(static_cast<std::int64_t>(c.misses));
    live_steps.push_back(static_cast<std::int64_t>(c.live_updates));
    retilings.push_back(static_cast<std::int64_t>(c.retilings));
    regenerations.push_back(static_cast<std::int64_t>(c.regenerations));
    dispersed_holds.push_back(static_cast<std::int64_t>(c.dispersed_holds));
    id.push_back(mp.id);
    connectivity.push_back(static_cast<std::int64_t>(k));
    offsets.push_back(static_cast<std::int64_t>(k + 1));
  }
  AppendedArrays arrays;
  arrays.add("velocity", "Float64", 3, velocity);
  arrays.add("stress", "Float64", 9, stress);
  arrays.add("pressure", "Float64", 1, pressure);
  arrays.add("deviatoric_stress", "Float64", 1, q);
  arrays.add("strain_rate_q", "Float64", 1, rate);
  arrays.add("damage", "Float64", 1, damage);
  arrays.add("density", "Float64", 1, density);
  arrays.add("law", "Int32", 1, law);
  arrays.add("source", "Int32", 1, source);  // StressSource: 0 analytic, 1 live, 2 hit, 3 miss
  arrays.add("estimated_error", "Float64", 1, error);
  // Per point since the start of the run: lookups within / beyond the tolerance, steps of a live cell.
  arrays.add("hits", "Int64", 1, hits);
  arrays.add("misses", "Int64", 1, misses);
  arrays.add("live_steps", "Int64", 1, live_steps);
  arrays.add("retilings", "Int64", 1, retilings);  // doublings of the point's live cell
  arrays.add("regenerations", "Int64", 1, regenerations);  // its cell replaced past the re-tiling cap
  arrays.add("dispersed_holds", "Int64", 1, dispersed_holds);  // dilations its dispersed cell did not take
  arrays.add("id", "Int64", 1, id);
  const std::string point_data = arrays.take_xml();
  arrays.add("points", "Float64", 3, xyz);
  const std::string point_xml = arrays.take_xml();
  arrays.add("connectivity", "Int64", 1, connectivity);
  arrays.add("offsets", "Int64", 1, offsets);
  arrays.add("types", "UInt8", 1, types);
  const std::string cell_xml = arrays.take_xml();

  std::ofstream out(file, std::ios::binary);
  if (!out) throw std::runtime_error(file.string() + ": cannot open for writing");
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <FieldData>\n"
      << "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">"
      << solver.time() << "</DataArray>\n"
      << "    </FieldData>\n"
      << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n"
      << "      <PointData Vectors=\"velocity\" Tensors=\"stress\">\n" << point_data << "      </PointData>\n"
      << "      <Points>\n" << point_xml << "      </Points>\n"
      << "      <Cells>\n" << cell_xml << "      </Cells>\n"
      << "    </Piece>\n"
      << "  </UnstructuredGrid>\n"
      << "  <AppendedData encoding=\"raw\">\n_";
  out.write(arrays.data().data(), static_cast<std::streamsize>(arrays.data().size()));
  out << "\n  </AppendedData>\n</VTKFile>\n";
  if (!out) throw std::runtime_error(file.string() + ": write failed");
}

void PvdCollection::add(double time, const std::string& relative_path) {
  entries_.emplace_back(time, relative_path);
  std::ofstream out(file_);
  if (!out) throw std::runtime_error(file_.string() + ": cannot open for writing");
  out.precision(17);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  for (const auto& [t, path] : entries_)
    out << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << path << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
  if (!out) throw std::runtime_error(file_.string() + ": write failed");
}

}  // namespace grainbank::mpm::io
