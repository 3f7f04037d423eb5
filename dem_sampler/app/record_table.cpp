#include "dem_sampler/app/record_table.hpp"

#include <cmath>
#include <iomanip>

namespace grainbank::app {
namespace {

constexpr int kAlignedWidth = 12;

double deviatoric_stress(const dem::Mat3& sigma) {
  const dem::Mat3 s = sigma - sigma.trace() / 3 * dem::Mat3::Identity();
  return std::sqrt(1.5 * s.cwiseProduct(s).sum());
}

}  // namespace

const std::vector<std::string>& record_columns() {
  static const std::vector<std::string> columns{
      "t",        "F_xx",     "F_xy",     "F_yx",     "F_yy",     "eps_v",    "sigma_xx", "sigma_yy",
      "sigma_zz", "sigma_xy", "sigma_xz", "sigma_yz", "p",        "q",        "phi",      "Z",
      "N_b",      "D",        "E_kin"};
  return columns;
}

std::vector<double> record_values(const PathRecord& r) {
  // The Cauchy stress is symmetric; the Love-Weber sum of a finite cell is so only up to fluctuations.
  // Report its symmetric part, as the library stores it.
  const dem::Mat3 s = 0.5 * (r.stress + r.stress.transpose());
  const dem::CellMeasures& m = r.measures;
  return {r.time,  r.F(0, 0), r.F(0, 1), r.F(1, 0), r.F(1, 1), std::log(r.F.determinant()),
          s(0, 0), s(1, 1),   s(2, 2),   s(0, 1),   s(0, 2),   s(1, 2),
          -s.trace() / 3, deviatoric_stress(s), m.solid_fraction, m.coordination,
          static_cast<double>(m.bonds), m.damage, m.kinetic_energy};
}

RecordTable::RecordTable(std::ostream& out, TableStyle style) : out_(out), style_(style) {}

void RecordTable::write_header() {
  const auto& columns = record_columns();
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (style_ == TableStyle::csv) out_ << (c ? "," : "") << columns[c];
    else out_ << (c ? " " : "") << std::setw(kAlignedWidth) << columns[c];
  }
  out_ << "\n";
}

void RecordTable::write(const PathRecord& record) {
  const std::vector<double> values = record_values(record);
  const auto flags = out_.flags();
  const auto precision = out_.precision();
  out_.unsetf(std::ios::floatfield);
  out_.precision(style_ == TableStyle::csv ? 10 : 5);
  for (std::size_t c = 0; c < values.size(); ++c) {
    if (style_ == TableStyle::csv) out_ << (c ? "," : "") << values[c];
    else out_ << (c ? " " : "") << std::setw(kAlignedWidth) << values[c];
  }
  out_ << "\n";
  out_.flags(flags);
  out_.precision(precision);
}

}  // namespace grainbank::app
