// Plain values packed into bytes and read back, for handing state between processes (MPI ranks) that
// run the same build on the same machine type: no format, no versioning, no byte-order conversion.
// Reading past the end throws, so a short or mismatched message is an error, not garbage.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace grainbank::common {

class ByteWriter {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    put_raw(&value, sizeof(T));
  }
  // A count, then the elements.
  template <class T>
  void put_vector(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<std::uint64_t>(values.size());
    put_raw(values.data(), values.size() * sizeof(T));
  }
  // A fixed-size Eigen matrix (not trivially copyable by the language's rules, plain doubles in fact).
  template <class Matrix>
  void put_matrix(const Matrix& m) {
    put_raw(m.data(), sizeof(typename Matrix::Scalar) * Matrix::SizeAtCompileTime);
  }
  void put_raw(const void* data, std::size_t size) {
    const std::size_t at = bytes_.size();
    bytes_.resize(at + size);
    if (size > 0) std::memcpy(bytes_.data() + at, data, size);
  }
  const std::vector<char>& bytes() const { return bytes_; }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class ByteReader {
 public:
  ByteReader(const char* data, std::size_t size) : data_(data), size_(size) {}
  explicit ByteReader(const std::vector<char>& bytes) : ByteReader(bytes.data(), bytes.size()) {}

  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    get_raw(&value, sizeof(T));
    return value;
  }
  template <class T>
  std::vector<T> get_vector() {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto count = get<std::uint64_t>();
    if (count > remaining() / sizeof(T))
      throw std::runtime_error("byte message: " + std::to_string(count) + " elements in " +
                               std::to_string(remaining()) + " bytes");
    std::vector<T> values(count);
    get_raw(values.data(), count * sizeof(T));
    return values;
  }
  template <class Matrix>
  Matrix get_matrix() {
    Matrix m;
    get_raw(m.data(), sizeof(typename Matrix::Scalar) * Matrix::SizeAtCompileTime);
    return m;
  }
  // Reads a count, then `read_one()` that many times.
  template <class ReadOne>
  auto get_each(ReadOne&& read_one) {
    const auto count = get<std::uint64_t>();
    if (count > remaining()) throw std::runtime_error("byte message: " + std::to_string(count) + " elements in " +
                                                      std::to_string(remaining()) + " bytes");
    std::vector<decltype(read_one())> values;
    values.reserve(count);
    for (std::uint64_t k = 0; k < count; ++k) values.push_back(read_one());
    return values;
  }
  void get_raw(void* out, std::size_t size) {
    if (size > remaining())
      throw std::runtime_error("byte message: " + std::to_string(size) + " bytes asked, " +
                               std::to_string(remaining()) + " left");
    std::memcpy(out, data_ + offset_, size);
    offset_ += size;
  }
  // The next `size` bytes as a reader of their own, skipped here.
  ByteReader take(std::size_t size) {
    if (size > remaining())
      throw std::runtime_error("byte message: " + std::to_string(size) + " bytes asked, " +
                               std::to_string(remaining()) + " left");
    ByteReader part(data_ + offset_, size);
    offset_ += size;
    return part;
  }
  std::size_t remaining() const { return size_ - offset_; }
  bool at_end() const { return offset_ == size_; }

 private:
  const char* data_;
  std::size_t size_, offset_ = 0;
};

}  // namespace grainbank::common
