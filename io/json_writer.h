#pragma once
// A small streaming JSON writer for the stats and info outputs (no dependency needed for writing).
#include <string>
#include <string_view>

namespace clothsim::io {

class JsonWriter {
 public:
  JsonWriter& begin_object() { comma(); s_ += '{'; first_ = true; return *this; }
  JsonWriter& end_object() { s_ += '}'; first_ = false; return *this; }
  JsonWriter& begin_array() { comma(); s_ += '['; first_ = true; return *this; }
  JsonWriter& end_array() { s_ += ']'; first_ = false; return *this; }
  JsonWriter& key(std::string_view k) { comma(); string_literal(k); s_ += ':'; first_ = true; return *this; }
  JsonWriter& value(double v);
  JsonWriter& value(long long v) { comma(); s_ += std::to_string(v); return *this; }
  JsonWriter& value(int v) { return value(static_cast<long long>(v)); }
  JsonWriter& value(long v) { return value(static_cast<long long>(v)); }  // std::int64_t on Linux
  JsonWriter& value(std::string_view v) { comma(); string_literal(v); return *this; }
  JsonWriter& value(bool v) { comma(); s_ += v ? "true" : "false"; return *this; }
  template <class T>
  JsonWriter& field(std::string_view k, T v) { key(k); return value(v); }
  const std::string& str() const { return s_; }

 private:
  void comma() { if (!first_) s_ += ','; first_ = false; }
  void string_literal(std::string_view v);
  std::string s_;
  bool first_ = true;
};

}  // namespace clothsim::io
