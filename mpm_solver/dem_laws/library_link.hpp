// A scene's connection to a cell library (DESIGN.md, "Nearest-state lookup"): the library opened
// for the material the scene expects (refused otherwise), the template its points start from, the
// nearest-state index over every done path and where the snapshots to warm-start from are.
//
// Promises: queries (index()) run concurrently from any thread; every other access to the library
// goes through locked(), which serialises it (HDF5 and the catalogue are not thread-safe).
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "dem_sampler/cell/dem_cell.hpp"
#include "mpm_solver/dem_laws/state_warm_start.hpp"
#include "database/lookup/lookup_index.hpp"
#include "database/store/library.hpp"

namespace grainbank::mpm {

class LibraryLink {
 public:
  // Opens the library in `dir` and indexes its done paths, with the key scales of the library's meta
  // or `scales` (keys are recomputed from each record's F, L and damage, so any scales are valid).
  // With `expected`, a library built for another material is refused (db::MaterialMismatch naming
  // the parameters); a missing template throws db::StoreError.
  LibraryLink(const std::filesystem::path& dir, std::int64_t template_id, const dem::Material* expected,
              const std::optional<db::KeyScales>& scales = std::nullopt);
  LibraryLink(const LibraryLink&) = delete;
  LibraryLink& operator=(const LibraryLink&) = delete;

  std::int64_t template_id() const { return template_id_; }
  const dem::DemCell& template_cell() const { return *template_cell_; }
  const lookup::LookupIndex& index() const { return *index_; }
  const db::KeyScales& scales() const { return index_->scales(); }
  // The stored cell to warm-start a state near record `ref` from: the last snapshot of its path at
  // or before that record; none when the path has no such snapshot (then start from the template).
  std::optional<db::StoredCell> snapshot_before(const lookup::RecordRef& ref);
  // Every snapshot of a done path of the template, with the state of the record it was taken after
  // (what a state warm start chooses among), in catalogue order.
  std::vector<StateSnapshot> state_snapshots();

  // Runs f(library) with the library to itself.
  template <class F>
  auto locked(F&& f) {
    const std::lock_guard<std::mutex> guard(mutex_);
    return f(library_);
  }

 private:
  db::Library library_;
  std::mutex mutex_;
  std::int64_t template_id_;
  std::optional<dem::DemCell> template_cell_;
  std::unique_ptr<lookup::LookupIndex> index_;
  std::map<std::int64_t, std::vector<std::int64_t>> snapshots_;     // by path: record indices, sorted
};

}  // namespace grainbank::mpm
