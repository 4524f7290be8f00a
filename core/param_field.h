#pragma once
// A per-element parameter that costs one scalar when it is uniform: element i is data[i * stride], with
// stride 0 over a single value, so kernels read both cases the same way, without a branch per element.
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

}  // namespace clothsim
