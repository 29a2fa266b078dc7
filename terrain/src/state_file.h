#pragma once
// Private: the byte writer and reader of the saved terrain state (terrain_io.cpp, whose
// top describes the layout, and spray_io.cpp). Numbers go in the writing machine's byte
// order; the reader fails with shore::FileError naming the file and what it was reading.

#include <cstddef>
#include <cstring>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "shore/core/error.h"

namespace shore::terrain {

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void put_doubles(const std::vector<double>& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    bytes.insert(bytes.end(), p, p + v.size() * sizeof(double));
  }
  std::vector<unsigned char> bytes;
};

class Reader {
 public:
  Reader(std::span<const unsigned char> bytes, std::size_t end, std::string file)
      : bytes_(bytes), end_(end), file_(std::move(file)) {}
  template <class T>
  T get(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  void get_doubles(std::vector<double>& v, const char* what) {
    need(v.size() * sizeof(double), what);
    std::memcpy(v.data(), bytes_.data() + pos_, v.size() * sizeof(double));
    pos_ += v.size() * sizeof(double);
  }
  std::string get_string(std::size_t size, const char* what) {
    need(size, what);
    std::string s(reinterpret_cast<const char*>(bytes_.data() + pos_), size);
    pos_ += size;
    return s;
  }
  [[nodiscard]] std::size_t remaining() const { return end_ - pos_; }
  [[noreturn]] void fail(const std::string& problem) const {
    throw FileError("terrain state " + file_ + ": " + problem);
  }

 private:
  void need(std::size_t size, const char* what) const {
    if (size > end_ - pos_) fail(std::string("truncated (file ends inside ") + what + ")");
  }
  std::span<const unsigned char> bytes_;
  std::size_t end_;
  std::size_t pos_ = 0;
  std::string file_;
};

}  // namespace shore::terrain
