// The work queue of a library's paths, for samplers: which paths are pending, and putting paths back
// to pending when their run was interrupted. A path put back loses its committed records and snapshot
// rows (its HDF5 data becomes an orphan, or is replaced when it restarts in the same shard): it will be
// run again from its template, which gives the same records (the engine is deterministic).
//
// These functions do not know whether a `running` path is still being worked on: the caller must
// hold the library's sampler lock (sampler_lock.hpp) when it resets paths it does not own.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "database/store/catalogue.hpp"

namespace grainbank::db {

// Ids of pending paths, ascending.
std::vector<std::int64_t> pending_paths(Catalogue& catalogue);

// An already registered path on this template with exactly this spec (JSON text), if any.
std::optional<std::int64_t> find_path(Catalogue& catalogue, std::int64_t template_id, const std::string& spec);

// Every `running` path (left by a killed writer) back to pending, in one transaction. Returns how many.
// The exception are paths recorded by an MPM run (enrichment: their spec has a "run" member), which
// no sampler can drive: they become `done` with the records they committed.
std::int64_t reset_running_paths(Catalogue& catalogue);

// These paths back to pending if they are running (a writer abandoning its own paths).
void reset_paths(Catalogue& catalogue, const std::vector<std::int64_t>& path_ids);

// Every `failed` path back to pending (error text cleared). Returns how many.
std::int64_t retry_failed_paths(Catalogue& catalogue);

}  // namespace grainbank::db
