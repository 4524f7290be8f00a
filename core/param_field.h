#pragma once
// A per-element parameter that costs one scalar when it is uniform: element i is data[i * stride], with
// stride 0 over a single value, so kernels read both cases the same way, without a branch per element.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/math.h"

namespace clothsim {

class ParamField {
 public:
  ParamField() : data_(1, 0.0) {}
  explicit ParamField(Real uniform) : data_(1, uniform) {}

  // Keeps one scalar when every value is equal (model no more than a scene needs).
  static ParamField from_values(std::vector<Real> values) {
    ParamField f;
    bool uniform = true;
    for (Real v : values) uniform = uniform && v == values.front();
    if (values.empty() || uniform) {
      f.data_.assign(1, values.empty() ? 0.0 : values.front());
      f.stride_ = 0;
    } else {
      f.data_ = std::move(values);
      f.stride_ = 1;
    }
    return f;
  }

  Real operator[](std::size_t i) const { return data_[i * stride_]; }
  bool uniform() const { return stride_ == 0; }
  const Real* data() const { return data_.data(); }
  std::size_t stride() const { return stride_; }
  std::size_t bytes() const { return data_.size() * sizeof(Real); }

 private:
  std::vector<Real> data_;
  std::size_t stride_ = 0;
};

// Collects a field value by value and keeps one scalar while they are all equal, so a uniform parameter never
// costs a per-element array, not even while the model is built (a million-particle sheet has six million
// springs: 48 MB a field). The first differing value turns it into the per-element array.
class ParamFieldBuilder {
 public:
  void push(Real v) {
    if (count_ == 0) first_ = v;
    if (values_.empty() && v != first_) values_.assign(count_, first_);
    if (!values_.empty()) values_.push_back(v);
    ++count_;
  }
  ParamField finish() {
    if (values_.empty()) return ParamField(count_ == 0 ? 0.0 : first_);
    return ParamField::from_values(std::move(values_));
  }

 private:
  std::vector<Real> values_;  // empty while every value equals first_
  Real first_ = 0;
  std::size_t count_ = 0;
};

}  // namespace clothsim
