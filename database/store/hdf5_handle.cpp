#include "database/store/hdf5_handle.hpp"

#include <utility>

namespace grainbank::db::h5 {
namespace {

// Once per process, before any other HDF5 call. Error printing is switched off: the exceptions carry
// the message instead. So is HDF5's clean-up at exit: after a failed write (disk full) it crashes
// closing the file whose close failed, and every object is closed by its owner before exit anyway.
void silence_hdf5() {
  static const bool done = [] {
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

// HDF5's messages may span lines ("file write failed: time = ...\n, filename = ..."); ours are one line.
herr_t collect_message(unsigned, const H5E_error2_t* error, void* out) {
  auto& messages = *static_cast<std::vector<std::string>*>(out);
  if (!error->desc || !*error->desc) return 0;
  std::string text = error->desc;
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  messages.push_back(std::move(text));
  return 0;
}

// The innermost HDF5 messages are the informative ones ("truncated file: eof = ...").
std::string hdf5_message() {
  std::vector<std::string> messages;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, collect_message, &messages);
  H5Eclear2(H5E_DEFAULT);
  if (messages.empty()) return "unknown HDF5 error";
  std::string text = messages.front();
  if (messages.size() > 1 && messages[1] != text) text += " (" + messages[1] + ")";
  return text;
}

// The size of the file holding object `id` when it is shorter than the space HDF5 allocated in it,
// else 0 (also when that cannot be told). With `read_only`, 0 for a file this process writes: what
// it reads there may not be flushed yet.
hsize_t cut_size(hid_t id, const std::filesystem::path& file, bool read_only) {
  const hid_t file_id = H5Iget_file_id(id);
  unsigned intent = 0;
  haddr_t allocated = 0;
  const bool known = file_id >= 0 && H5Fget_intent(file_id, &intent) >= 0 && H5Fget_eoa(file_id, &allocated) >= 0;
  if (file_id >= 0) H5Fclose(file_id);
  H5Eclear2(H5E_DEFAULT);
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(file, error);
  if (!known || error || (read_only && (intent & H5F_ACC_RDWR))) return 0;
  return allocated > size ? size : 0;
}

// A read of a file shorter than the space HDF5 allocated in it fails on zeros ("bad object header
// version", a checksum): the note names the cause.
std::string truncation_note(hid_t id, const std::filesystem::path& file) {
  const hsize_t size = cut_size(id, file, false);
  return size ? " (the file is truncated: " + std::to_string(size) + " bytes, less than HDF5 allocated)" : "";
}

std::string child_path(const Object& parent, const std::string& name) {
  if (name.starts_with('/')) return name;
  return parent.name() == "/" ? "/" + name : parent.name() + "/" + name;
}

Object file_object(hid_t id, const std::filesystem::path& file, const std::string& what) {
  if (id < 0) throw StoreError(file, what + ": " + hdf5_message());
  return Object(id, H5Fclose, file, "/");
}

// Newest 1.10 file format: its metadata carries checksums, so damage is reported instead of misread.
Object file_access() {
  silence_hdf5();
  Object fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "", "");
  H5Pset_libver_bounds(fapl.id(), H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
  return fapl;
}

bool open_in_this_process(const std::filesystem::path& file) {
  const ssize_t count = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE);
  if (count <= 0) return false;
  std::vector<hid_t> ids(static_cast<std::size_t>(count));
  const ssize_t listed = H5Fget_obj_ids(H5F_OBJ_ALL, H5F_OBJ_FILE, ids.size(), ids.data());
  for (ssize_t k = 0; k < listed; ++k) {
    char name[4096];
    std::error_code ignored;
    if (H5Fget_name(ids[static_cast<std::size_t>(k)], name, sizeof name) > 0 &&
        std::filesystem::equivalent(name, file, ignored))
      return true;
  }
  return false;
}

// Readers must neither block the shard's writer nor fail while it writes or after it was killed, but
// HDF5 1.10 refuses all three: by a file lock, by the "open for write" flag a writer sets in the
// superblock, and when the file is shorter than the space the superblock allocates (a writer killed
// in its flush, after the superblock reached the disk and before the data it allocated did).
// Readers take no lock, ignore the flag in their in-memory copy of the superblock and skip the size
// check (the properties h5clear uses; the file is not touched: extending it under a live writer
// could cut off what it writes meanwhile). This is safe because readers follow committed rows only,
// which the writer flushed before committing and never changes afterwards, so they lie within the
// file; the bytes beyond its end would read as zeros, which metadata checksums reject and
// require_on_disk() refuses for raw data. (A file this process already has open is shared by HDF5,
// which then insists on the settings it was opened with.)
void ignore_writer_state(const Object& fapl) {
  hbool_t yes = true;
  if (H5Pset(fapl.id(), "clear_status_flags", &yes) < 0 || H5Pset(fapl.id(), "skip_eof_check", &yes) < 0)
    fapl.fail("cannot set the properties of h5clear");
}

void allow_concurrent_writer(const Object& fapl) {
  if (H5Pset_file_locking(fapl.id(), false, true) < 0) fapl.fail("cannot disable file locking");
  ignore_writer_state(fapl);
}

[[noreturn]] void fail_beyond_end(const Object& dataset, haddr_t end, hsize_t size) {
  throw StoreError(dataset.file(), dataset.name() + ": data beyond the end of the file (truncated: the file has " +
                                       std::to_string(size) + " bytes, the data ends at " + std::to_string(end) + ")");
}

// Raw data read from a file cut short must lie before the cut: beyond it HDF5 reads zeros, which
// contiguous arrays do not check and Fletcher-32 accepts (its checksum of zeros is zero).
void require_on_disk(const Object& dataset, hsize_t first_row, hsize_t rows, hsize_t columns) {
  const hsize_t size = cut_size(dataset.id(), dataset.file(), true);
  if (size == 0 || rows == 0) return;
  const haddr_t offset = H5Dget_offset(dataset.id());
  if (offset != HADDR_UNDEF) {  // contiguous
    const haddr_t end = offset + H5Dget_storage_size(dataset.id());
    if (end > size) fail_beyond_end(dataset, end, size);
    return;
  }
  const Object plist(H5Dget_create_plist(dataset.id()), H5Pclose, dataset.file(), dataset.name());
  if (H5Pget_layout(plist.id()) != H5D_CHUNKED) return;  // compact: inside the checksummed header
  hsize_t chunk[2] = {1, columns};
  H5Pget_chunk(plist.id(), 2, chunk);
  for (hsize_t row = first_row - first_row % chunk[0]; row < first_row + rows; row += chunk[0]) {
    const hsize_t at[2] = {row, 0};
    unsigned filter_mask = 0;
    haddr_t address = HADDR_UNDEF;
    hsize_t bytes = 0;
    if (H5Dget_chunk_info_by_coord(dataset.id(), at, &filter_mask, &address, &bytes) < 0)
      dataset.fail("cannot locate the chunk of row " + std::to_string(row));
    if (address != HADDR_UNDEF && address + bytes > size) fail_beyond_end(dataset, address + bytes, size);
  }
}

}  // namespace

Object::Object(hid_t id, herr_t (*close)(hid_t), std::filesystem::path file, std::string name)
    : id_(id), close_(close), file_(std::move(file)), name_(std::move(name)) {}

Object::~Object() {
  if (id_ >= 0) close_(id_);
}

Object::Object(Object&& other) noexcept
    : id_(std::exchange(other.id_, -1)), close_(other.close_), file_(std::move(other.file_)), name_(std::move(other.name_)) {}

void Object::fail(const std::string& what) const {
  const std::string message = hdf5_message();
  throw StoreError(file_, name_ + ": " + what + ": " + message + truncation_note(id_, file_));
}

Object create_file(const std::filesystem::path& file) {
  const Object fapl = file_access();
  return file_object(H5Fcreate(file.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, fapl.id()), file, "cannot create the HDF5 file");
}

Object open_file(const std::filesystem::path& file, bool writable) {
  if (!std::filesystem::exists(file)) throw StoreError(file, "HDF5 file is missing");
  const Object fapl = file_access();
  if (!writable && !open_in_this_process(file)) allow_concurrent_writer(fapl);
  const hid_t id = H5Fopen(file.c_str(), writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, fapl.id());
  return file_object(id, file, "not a readable HDF5 file (truncated, corrupt, or open for writing elsewhere)");
}

namespace {

// Opens with the private properties h5clear uses (as readers do): the "open for write" flag ignored
// (and cleared on closing a writable open) and no check of the file size against the space the
// superblock allocates.
Object open_as_h5clear(const std::filesystem::path& file, bool writable) {
  const Object fapl = file_access();
  if (writable)
    ignore_writer_state(fapl);
  else
    allow_concurrent_writer(fapl);
  return file_object(H5Fopen(file.c_str(), writable ? H5F_ACC_RDWR : H5F_ACC_RDONLY, fapl.id()), file,
                     "cannot open the shard even as h5clear does (damaged? run celldb verify)");
}

haddr_t end_of_allocation(const Object& root) {
  haddr_t end = 0;
  if (H5Fget_eoa(root.id(), &end) < 0) root.fail("cannot read the end of allocated space");
  return end;
}

}  // namespace

bool cut_short(const std::filesystem::path& file) {
  try {
    return end_of_allocation(open_as_h5clear(file, false)) > std::filesystem::file_size(file);
  } catch (const StoreError&) {
    return false;
  }
}

void clear_stale_writer_state(const std::filesystem::path& file) {
  // Closing the writable open writes the superblock back with the flags cleared.
  const haddr_t end = end_of_allocation(open_as_h5clear(file, true));
  // The committed data lies before the end of the file (it was flushed before its commit); the
  // missing tail held uncommitted data only.
  if (end > std::filesystem::file_size(file)) std::filesystem::resize_file(file, end);
}

void flush(const Object& file) {
  if (H5Fflush(file.id(), H5F_SCOPE_GLOBAL) < 0) file.fail("cannot flush");
}

Object create_group(const Object& parent, const std::string& name) {
  const std::string path = child_path(parent, name);
  const hid_t id = H5Gcreate2(parent.id(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (id < 0) parent.fail("cannot create group " + name);
  return Object(id, H5Gclose, parent.file(), path);
}

Object open_group(const Object& parent, const std::string& name) {
  const hid_t id = H5Gopen2(parent.id(), name.c_str(), H5P_DEFAULT);
  if (id < 0) parent.fail("missing or unreadable group " + name);
  return Object(id, H5Gclose, parent.file(), child_path(parent, name));
}

bool has_child(const Object& parent, const std::string& name) {
  const htri_t found = H5Lexists(parent.id(), name.c_str(), H5P_DEFAULT);
  if (found < 0) parent.fail("cannot look up " + name);
  return found > 0;
}

namespace {
herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}
}  // namespace

std::vector<std::string> child_names(const Object& group) {
  std::vector<std::string> names;
  if (H5Literate(group.id(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &names) < 0)
    group.fail("cannot list members");
  return names;
}

void remove_child(const Object& parent, const std::string& name) {
  if (H5Ldelete(parent.id(), name.c_str(), H5P_DEFAULT) < 0) parent.fail("cannot remove " + name);
}

void copy_object(const Object& from, const Object& to, const std::string& name) {
  if (H5Ocopy(from.id(), name.c_str(), to.id(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT) < 0)
    from.fail("cannot copy " + name + " to " + to.file().string());
}

template <class T>
void write_array(const Object& parent, const std::string& name, const std::vector<T>& data, hsize_t columns) {
  const hsize_t rows = columns ? data.size() / columns : data.size();
  const hsize_t dims[2] = {rows, columns};
  const Object space(H5Screate_simple(columns ? 2 : 1, dims, nullptr), H5Sclose, parent.file(), "");
  // One chunk with a Fletcher-32 checksum: HDF5 checks it on every read, so a damaged byte of a stored
  // cell (a template, a snapshot, a restart) is refused instead of read as another state. An empty
  // array cannot be chunked and has no data to damage.
  const Object dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, parent.file(), "");
  if (rows > 0 && (H5Pset_chunk(dcpl.id(), columns ? 2 : 1, dims) < 0 || H5Pset_fletcher32(dcpl.id()) < 0))
    parent.fail("cannot set the checksum of dataset " + name);
  const hid_t id =
      H5Dcreate2(parent.id(), name.c_str(), native_type<T>(), space.id(), H5P_DEFAULT, dcpl.id(), H5P_DEFAULT);
  if (id < 0) parent.fail("cannot create dataset " + name);
  const Object dataset(id, H5Dclose, parent.file(), child_path(parent, name));
  if (!data.empty() && H5Dwrite(id, native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    dataset.fail("cannot write");
}

Object open_dataset(const Object& parent, const std::string& name) {
  const hid_t id = H5Dopen2(parent.id(), name.c_str(), H5P_DEFAULT);
  if (id < 0) parent.fail("missing or unreadable dataset " + name);
  return Object(id, H5Dclose, parent.file(), child_path(parent, name));
}

namespace {
std::vector<hsize_t> dataset_dims(const Object& dataset) {
  const Object space(H5Dget_space(dataset.id()), H5Sclose, dataset.file(), dataset.name());
  const int rank = H5Sget_simple_extent_ndims(space.id());
  if (rank < 0) dataset.fail("cannot read its shape");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id(), dims.data(), nullptr);
  return dims;
}
}  // namespace

template <class T>
std::vector<T> read_array(const Object& parent, const std::string& name, hsize_t columns) {
  const Object dataset = open_dataset(parent, name);
  const std::vector<hsize_t> dims = dataset_dims(dataset);
  const bool shape_ok = columns ? dims.size() == 2 && dims[1] == columns : dims.size() == 1;
  if (!shape_ok)
    throw StoreError(dataset.file(), dataset.name() + ": unexpected shape (expected " +
                                         (columns ? "N x " + std::to_string(columns) : std::string("N")) + ")");
  std::vector<T> data(dims[0] * (columns ? columns : 1));
  require_on_disk(dataset, 0, dims[0], columns);
  if (!data.empty() && H5Dread(dataset.id(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    dataset.fail("cannot read");
  return data;
}

template void write_array(const Object&, const std::string&, const std::vector<double>&, hsize_t);
template void write_array(const Object&, const std::string&, const std::vector<std::int64_t>&, hsize_t);
template void write_array(const Object&, const std::string&, const std::vector<std::uint32_t>&, hsize_t);
template void write_array(const Object&, const std::string&, const std::vector<std::uint8_t>&, hsize_t);
template std::vector<double> read_array(const Object&, const std::string&, hsize_t);
template std::vector<std::int64_t> read_array(const Object&, const std::string&, hsize_t);
template std::vector<std::uint32_t> read_array(const Object&, const std::string&, hsize_t);
template std::vector<std::uint8_t> read_array(const Object&, const std::string&, hsize_t);

namespace {
Object utf8_string_type(const Object& owner) {
  Object type(H5Tcopy(H5T_C_S1), H5Tclose, owner.file(), owner.name());
  H5Tset_size(type.id(), H5T_VARIABLE);
  H5Tset_cset(type.id(), H5T_CSET_UTF8);
  return type;
}

void write_attribute_raw(const Object& object, const std::string& name, hid_t type, hsize_t count, bool scalar,
                         const void* data) {
  const Object space(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &count, nullptr), H5Sclose, object.file(), "");
  const hid_t id = H5Acreate2(object.id(), name.c_str(), type, space.id(), H5P_DEFAULT, H5P_DEFAULT);
  if (id < 0) object.fail("cannot create attribute " + name);
  const Object attribute(id, H5Aclose, object.file(), object.name());
  if (H5Awrite(id, type, data) < 0) object.fail("cannot write attribute " + name);
}

Object open_attribute(const Object& object, const std::string& name) {
  const hid_t id = H5Aopen(object.id(), name.c_str(), H5P_DEFAULT);
  if (id < 0) object.fail("missing attribute " + name);
  return Object(id, H5Aclose, object.file(), object.name());
}
}  // namespace

void write_attribute(const Object& object, const std::string& name, double value) {
  write_attribute_raw(object, name, H5T_NATIVE_DOUBLE, 1, true, &value);
}
void write_attribute(const Object& object, const std::string& name, std::int64_t value) {
  write_attribute_raw(object, name, H5T_NATIVE_INT64, 1, true, &value);
}
void write_attribute(const Object& object, const std::string& name, const std::string& value) {
  const char* text = value.c_str();
  write_attribute_raw(object, name, utf8_string_type(object).id(), 1, true, &text);
}
void write_attribute(const Object& object, const std::string& name, const std::vector<std::string>& values) {
  std::vector<const char*> texts;
  for (const std::string& v : values) texts.push_back(v.c_str());
  write_attribute_raw(object, name, utf8_string_type(object).id(), texts.size(), false, texts.data());
}

double read_double_attribute(const Object& object, const std::string& name) {
  double value = 0;
  if (H5Aread(open_attribute(object, name).id(), H5T_NATIVE_DOUBLE, &value) < 0)
    object.fail("cannot read attribute " + name);
  return value;
}
std::int64_t read_int_attribute(const Object& object, const std::string& name) {
  std::int64_t value = 0;
  if (H5Aread(open_attribute(object, name).id(), H5T_NATIVE_INT64, &value) < 0)
    object.fail("cannot read attribute " + name);
  return value;
}
std::string read_string_attribute(const Object& object, const std::string& name) {
  const Object attribute = open_attribute(object, name);
  char* text = nullptr;
  if (H5Aread(attribute.id(), utf8_string_type(object).id(), &text) < 0) object.fail("cannot read attribute " + name);
  std::string value = text ? text : "";
  H5free_memory(text);
  return value;
}

Object create_table(const Object& parent, const std::string& name, hsize_t columns, hsize_t chunk_rows) {
  const hsize_t dims[2] = {0, columns};
  const hsize_t max_dims[2] = {H5S_UNLIMITED, columns};
  const hsize_t chunk[2] = {chunk_rows, columns};
  const Object space(H5Screate_simple(2, dims, max_dims), H5Sclose, parent.file(), "");
  const Object dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, parent.file(), "");
  H5Pset_chunk(dcpl.id(), 2, chunk);
  H5Pset_fletcher32(dcpl.id());
  const hid_t id =
      H5Dcreate2(parent.id(), name.c_str(), H5T_NATIVE_DOUBLE, space.id(), H5P_DEFAULT, dcpl.id(), H5P_DEFAULT);
  if (id < 0) parent.fail("cannot create table " + name);
  return Object(id, H5Dclose, parent.file(), child_path(parent, name));
}

hsize_t table_rows(const Object& table) { return dataset_dims(table).at(0); }

hsize_t table_columns(const Object& table) {
  const std::vector<hsize_t> dims = dataset_dims(table);
  if (dims.size() != 2) throw StoreError(table.file(), table.name() + ": expected a two-dimensional table");
  return dims[1];
}

void resize_rows(const Object& table, hsize_t rows) {
  const hsize_t dims[2] = {rows, table_columns(table)};
  if (H5Dset_extent(table.id(), dims) < 0) table.fail("cannot resize to " + std::to_string(rows) + " rows");
}

void append_rows(const Object& table, const std::vector<double>& rows) {
  const hsize_t columns = table_columns(table);
  const hsize_t first = table_rows(table);
  const hsize_t count[2] = {rows.size() / columns, columns};
  if (count[0] == 0) return;
  resize_rows(table, first + count[0]);
  const Object file_space(H5Dget_space(table.id()), H5Sclose, table.file(), table.name());
  const hsize_t start[2] = {first, 0};
  H5Sselect_hyperslab(file_space.id(), H5S_SELECT_SET, start, nullptr, count, nullptr);
  const Object memory_space(H5Screate_simple(2, count, nullptr), H5Sclose, table.file(), table.name());
  if (H5Dwrite(table.id(), H5T_NATIVE_DOUBLE, memory_space.id(), file_space.id(), H5P_DEFAULT, rows.data()) < 0)
    table.fail("cannot append " + std::to_string(count[0]) + " rows");
}

std::vector<double> read_rows(const Object& table, hsize_t first, hsize_t count) {
  const hsize_t columns = table_columns(table);
  const hsize_t rows = table_rows(table);
  if (first + count > rows)
    throw StoreError(table.file(), table.name() + ": has " + std::to_string(rows) + " rows, " +
                                       std::to_string(first + count) + " expected");
  std::vector<double> data(count * columns);
  if (count == 0) return data;
  require_on_disk(table, first, count, columns);
  const Object file_space(H5Dget_space(table.id()), H5Sclose, table.file(), table.name());
  const hsize_t start[2] = {first, 0};
  const hsize_t size[2] = {count, columns};
  H5Sselect_hyperslab(file_space.id(), H5S_SELECT_SET, start, nullptr, size, nullptr);
  const Object memory_space(H5Screate_simple(2, size, nullptr), H5Sclose, table.file(), table.name());
  if (H5Dread(table.id(), H5T_NATIVE_DOUBLE, memory_space.id(), file_space.id(), H5P_DEFAULT, data.data()) < 0)
    table.fail("cannot read rows (corrupt data: checksum or read error)");
  return data;
}

}  // namespace grainbank::db::h5
