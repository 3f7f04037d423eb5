// The library-backed laws (DESIGN.md, "Macro scale: MPM"): `cache` and `hybrid`.
//
// Every step a cached point computes its state key from its deformation gradient F, the velocity
// gradient L of its increment and its damage, and asks the
// library: the answer's stress (rotated into the point's frame) becomes its stress, its blended
// damage, coordination and solid fraction the point's damage and wave speed. A hit is a nearest
// record within the tolerance.
// - cache: a miss is answered by the same nearest-state blend and counted (fastest, least accurate).
// - hybrid: a miss turns the point live. Its cell is built (warm start: the last snapshot at or
//   before the nearest record, or the template, driven to the point's F before this increment;
//   replay: the template re-run through the point's own recorded increments), then receives this
//   step's increment, and from then on the point behaves as a point of the live law (two-way
//   coupling, LiveCellModel). A live point goes back to the cache only after its own state has been
//   within the tolerance for `return_after` consecutive steps (0: it stays live). With `enrich`, the
//   responses of live cells are written to the run's own shard (enrichment.hpp).
// With an empty library every hybrid point turns live at its first step from the template itself,
// so the run equals the live law's to round-off.
#pragma once
#include <atomic>
#include <memory>
#include <optional>
#include <vector>

#include "mpm_solver/core/constitutive_law.hpp"
#include "mpm_solver/core/dem_backed_law.hpp"
#include "mpm_solver/core/point_sharing.hpp"
#include "mpm_solver/dem_laws/enrichment.hpp"
#include "mpm_solver/dem_laws/library_link.hpp"
#include "mpm_solver/dem_laws/live_cell_model.hpp"
#include "mpm_solver/dem_laws/warm_start.hpp"

namespace grainbank::mpm {

enum class Fallback { none, warm_start, replay };  // none = the cache law

struct LibraryLawSettings {
  lookup::LookupOptions lookup;  // k and the hit tolerance (key units)
  Fallback fallback = Fallback::none;
  double max_drive_strain = 1e-3;  // warm start: largest log strain per driving increment
  int return_after = 0;            // steps inside the tolerance before a live point is cached again
  bool enrich = false;             // write live responses to the run's own shard
  int snapshot_interval = 25;      // of enriched paths: a snapshot every this many records
  long snapshot_budget = Enrichment::kUnlimited;  // snapshots the run may add in all
  LiveDemSettings live;            // of the live cells (and of the wave speed of cached points)
  // A run spread over MPI ranks: this rank and their number. Rank 0 leads the enrichment (the
  // library's lock); each rank writes its own shard with its share of the snapshot budget.
  int rank = 0, ranks = 1;
};

class LibraryLaw : public ConstitutiveLaw, public DemBackedLaw, public PointSharing {
 public:
  // Throws std::invalid_argument on bad settings or when the cache law gets an empty library.
  LibraryLaw(std::unique_ptr<LibraryLink> link, LibraryLawSettings settings);
  ~LibraryLaw() override;

  std::string name() const override { return settings_.fallback == Fallback::none ? "cache" : "hybrid"; }
  double density() const override { return model_.density(); }
  std::size_t add_point(PointStress& initial_stress) override;
  void update(std::size_t slot, const KinematicIncrement& increment, const Mat2& F, PointStress& stress) override;
  double volume_ratio(std::size_t slot, double kinematic) const override;
  double p_wave_modulus(std::size_t slot) const override { return points_[slot].modulus; }
  double time_step_limit(std::size_t slot, const Mat2& F, const Mat2& L) const override;
  double damage(std::size_t slot) const override { return points_[slot].damage; }
  bool expensive() const override { return live_points_ > 0; }
  // The cache law's answers depend on the point and the (read-only) library alone: every rank of a
  // spread run gives them alike.
  bool replicable() const override { return settings_.fallback == Fallback::none; }
  // Hybrid points are spread over ranks like live ones: each rank looks up, turns live and drives
  // its own points; the others keep each point's damage, modulus, source and counters (the
  // summary), and receive its whole state (live cell, replay history) when they must hold it.
  PointSharing* point_sharing() override { return settings_.fallback == Fallback::none ? nullptr : this; }
  void write_summary(std::size_t slot, common::ByteWriter& out) const override;
  void read_summary(std::size_t slot, common::ByteReader& in) override;
  void write_point_state(std::size_t slot, common::ByteWriter& out) const override;
  void read_point_state(std::size_t slot, common::ByteReader& in) override;
  // A live point that moved to another rank ends its enriched path here; its new rank starts one.
  void release(std::size_t slot) override;
  // Per point its damage, whether it is live, its steps inside the tolerance, its replay history and
  // its live cell. A restored live point starts a new enriched path.
  void save_state(LawStateWriter& out) const override;
  void restore_state(LawStateReader& in) override;
  // Marks the enriched paths of the live points done. Idempotent.
  void finish() override;
  const DemBackedLaw* dem_backed() const override { return this; }

  StressSource source(std::size_t slot) const override { return points_[slot].source; }
  double estimated_error(std::size_t slot) const override { return points_[slot].error; }
  CouplingCounters point_counters(std::size_t slot) const override { return points_[slot].counters; }
  const dem::DemCell* live_cell(std::size_t slot) const override { return points_[slot].cell.get(); }
  // The sum of the point counters.
  CouplingCounters counters() const;

  const LibraryLink& link() const { return *link_; }

 private:
  struct Point {
    double damage = 0, modulus = 0, error = 0;
    StressSource source = StressSource::hit;
    std::unique_ptr<dem::DemCell> cell;          // live only
    int steps_inside = 0;                        // consecutive live steps within the tolerance
    std::vector<KinematicIncrement> history;     // replay only
    RunPath path;                                // enrichment of the live cell
    CouplingCounters counters;
  };

  lookup::LookupAnswer ask(const Point& p, const Mat2& F, const Mat2& L) const;
  void go_live(std::size_t slot, Point& p, const Mat2& F_before, const lookup::LookupAnswer& answer, double dt);
  void advance_live(Point& p, const KinematicIncrement& increment, PointStress& stress);
  void start_enriched_path(Point& p, const nlohmann::json& origin);

  std::unique_ptr<LibraryLink> link_;
  LibraryLawSettings settings_;
  LiveCellModel model_;
  dem::CellMeasures template_measures_;
  std::unique_ptr<Enrichment> enrichment_;
  std::vector<Point> points_;
  std::atomic<long> live_points_{0};  // updated by the threads that turn points live or back
};

}  // namespace grainbank::mpm
