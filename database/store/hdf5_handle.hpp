// A thin RAII layer over the HDF5 C API: owned handles, typed arrays, attributes and extendible
// tables. Every failure throws StoreError naming the shard file, the object inside it and the
// innermost HDF5 message ("truncated file", "bad object header checksum", ...). HDF5's own printing
// of error stacks is switched off: errors reach the user once, through the exception.
#pragma once
#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "database/store/error.hpp"

namespace grainbank::db::h5 {

class Object {
 public:
  Object(hid_t id, herr_t (*close)(hid_t), std::filesystem::path file, std::string name);
  ~Object();
  Object(Object&& other) noexcept;
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;
  Object& operator=(Object&&) = delete;

  hid_t id() const { return id_; }
  const std::filesystem::path& file() const { return file_; }
  const std::string& name() const { return name_; }  // path inside the file, e.g. "/paths/3"
  // Throws StoreError("<file>: <object>: <what>: <HDF5 message>").
  [[noreturn]] void fail(const std::string& what) const;

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
  std::filesystem::path file_;
  std::string name_;
};

// Files use the newest format of HDF5 1.10 (checksummed metadata, so corruption is detected rather
// than misread). Opening refuses foreign files; a writable open also refuses truncated ones (HDF5
// compares the file size with the end of the space it allocated).
Object create_file(const std::filesystem::path& file);
// Read-only opens take no file lock, so readers never block the one writer of a shard, and accept a
// file shorter than its allocated space, as a writer killed in its flush leaves it: committed data
// lies before the cut and reads back; a read of data beyond it fails ("truncated").
Object open_file(const std::filesystem::path& file, bool writable);
void flush(const Object& file);
// For a shard no writer has open any more (the caller knows, e.g. by the sampler lock): clears the
// "open for write" flag a killed writer leaves (as h5clear -s) and extends a file its writer could
// not extend (disk full) to the size its superblock records, so HDF5 opens it again.
void clear_stale_writer_state(const std::filesystem::path& file);
// True when the file is shorter than the space its superblock allocates: HDF5 then refuses to open
// it, and clear_stale_writer_state extends it back.
bool cut_short(const std::filesystem::path& file);

Object create_group(const Object& parent, const std::string& name);
Object open_group(const Object& parent, const std::string& name);
bool has_child(const Object& parent, const std::string& name);
std::vector<std::string> child_names(const Object& group);
// Unlinks a child; HDF5 does not give the space back (h5repack does). Fails when the child's own
// object header is unreadable (unlinking updates it): Shard::rewrite_without handles that case.
void remove_child(const Object& parent, const std::string& name);
// Copies the object `name` of `from` (a group with everything below it, or a dataset, attributes
// included) to the same path in `to`, whose parent group must exist.
void copy_object(const Object& from, const Object& to, const std::string& name);

// Element types stored in shards.
template <class T>
hid_t native_type();
template <> inline hid_t native_type<double>() { return H5T_NATIVE_DOUBLE; }
template <> inline hid_t native_type<std::int64_t>() { return H5T_NATIVE_INT64; }
template <> inline hid_t native_type<std::uint32_t>() { return H5T_NATIVE_UINT32; }
template <> inline hid_t native_type<std::uint8_t>() { return H5T_NATIVE_UINT8; }

// Fixed-size arrays of rank 1 (columns = 0) or 2 (rows × columns), C order, each stored as one chunk
// with a Fletcher-32 checksum (an empty one contiguous): a damaged byte fails the read. Arrays that
// older builds wrote contiguous, without a checksum, read the same.
template <class T>
void write_array(const Object& parent, const std::string& name, const std::vector<T>& data, hsize_t columns);
// Reads an array written by write_array; throws unless its shape is rows × columns (any rows).
template <class T>
std::vector<T> read_array(const Object& parent, const std::string& name, hsize_t columns);

void write_attribute(const Object& object, const std::string& name, double value);
void write_attribute(const Object& object, const std::string& name, std::int64_t value);
void write_attribute(const Object& object, const std::string& name, const std::string& value);
void write_attribute(const Object& object, const std::string& name, const std::vector<std::string>& values);
double read_double_attribute(const Object& object, const std::string& name);
std::int64_t read_int_attribute(const Object& object, const std::string& name);
std::string read_string_attribute(const Object& object, const std::string& name);

// Tables of doubles that grow by rows: chunked, unlimited rows, Fletcher-32 checksums per chunk.
Object create_table(const Object& parent, const std::string& name, hsize_t columns, hsize_t chunk_rows);
Object open_dataset(const Object& parent, const std::string& name);
hsize_t table_rows(const Object& table);
hsize_t table_columns(const Object& table);
void append_rows(const Object& table, const std::vector<double>& rows);
// Shrinks (or grows) the table to `rows`.
void resize_rows(const Object& table, hsize_t rows);
// Rows [first, first + count) in C order.
std::vector<double> read_rows(const Object& table, hsize_t first, hsize_t count);

}  // namespace grainbank::db::h5
