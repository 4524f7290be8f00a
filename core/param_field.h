#pragma once
// A per-element parameter that costs only what varies. Three forms, so kernels read every one the same way:
// - uniform: one value (stride 0);
// - palette: at most palette_max distinct values and one byte per element naming its value (a Provot grid whose
//   kinds have different scales, or a map of a few grey levels: 1 byte per spring instead of 8, and the
//   vectorised spring kernel reads the value from a table in L1 instead of a streamed array);
// - per element: one value each, element i is data[i].
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/math.h"

namespace clothsim {

class ParamField {
 public:
  static constexpr std::size_t palette_max = 16;
  enum class Form { uniform, palette, per_element };

  ParamField() : data_(1, 0.0) {}
  explicit ParamField(Real uniform) : data_(1, uniform) {}

  // Keeps one scalar when every value is equal (model no more than a scene needs), else one value per element.
  static ParamField from_values(std::vector<Real> values) {
    ParamField f;
    bool uniform = true;
    for (Real v : values) uniform = uniform && v == values.front();
    if (values.empty() || uniform) {
      f.data_.assign(1, values.empty() ? 0.0 : values.front());
      f.stride_ = 0;
    } else {
      f.data_ = std::move(values);
      f.data_.shrink_to_fit();  // held for the model's life: no spare capacity from a builder's growth
      f.stride_ = 1;
    }
    return f;
  }

  // The palette form: element i is palette[code[i]]. Every code must name a palette entry.
  static ParamField from_palette(std::vector<Real> palette, std::vector<std::uint8_t> code) {
    ParamField f;
    f.data_ = std::move(palette);
    f.code_ = std::move(code);
    f.data_.shrink_to_fit();
    f.code_.shrink_to_fit();
    return f;
  }

  Real operator[](std::size_t i) const { return code_.empty() ? data_[i * stride_] : data_[code_[i]]; }
  // Element i of a field known to be of form F: what a hot loop reads after choosing its form once (with_forms).
  template <Form F>
  Real at(std::size_t i) const {
    if constexpr (F == Form::uniform) return data_[0];
    else if constexpr (F == Form::palette) return data_[code_[i]];
    else return data_[i];
  }
  Form form() const { return uniform() ? Form::uniform : paletted() ? Form::palette : Form::per_element; }
  bool uniform() const { return stride_ == 0 && code_.empty(); }
  bool paletted() const { return !code_.empty(); }
  // uniform: the value; palette: the palette; per element: the values.
  const Real* data() const { return data_.data(); }
  std::size_t size() const { return data_.size(); }
  // palette: the code of each element (empty in the other forms)
  const std::uint8_t* code() const { return code_.data(); }
  std::size_t stride() const { return stride_; }
  std::size_t bytes() const { return data_.size() * sizeof(Real) + code_.size(); }

 private:
  std::vector<Real> data_;
  std::vector<std::uint8_t> code_;  // palette form only
  std::size_t stride_ = 0;          // 1 in the per-element form
};

// Calls body(std::integral_constant<ParamField::Form, ...>{} for a, ... for b): a kernel instantiated once per
// pair of forms, chosen outside its loop, so each field costs only what its form needs.
template <class Body>
decltype(auto) with_forms(const ParamField& a, const ParamField& b, Body&& body) {
  using F = ParamField::Form;
  auto second = [&](auto fa) -> decltype(auto) {
    switch (b.form()) {
      case F::uniform: return body(fa, std::integral_constant<F, F::uniform>{});
      case F::palette: return body(fa, std::integral_constant<F, F::palette>{});
      default: return body(fa, std::integral_constant<F, F::per_element>{});
    }
  };
  switch (a.form()) {
    case F::uniform: return second(std::integral_constant<F, F::uniform>{});
    case F::palette: return second(std::integral_constant<F, F::palette>{});
    default: return second(std::integral_constant<F, F::per_element>{});
  }
}

// Collects a field value by value in the cheapest form that holds it, so a uniform parameter never costs a
// per-element array, not even while the model is built (a million-particle sheet has six million springs:
// 48 MB a field). While every value equals the first it keeps one scalar; up to ParamField::palette_max
// distinct values, a palette and one byte per element; the value after that turns it into the per-element array.
class ParamFieldBuilder {
 public:
  void push(Real v) {
    if (!values_.empty()) {
      values_.push_back(v);
    } else if (palette_.empty() || v != palette_[last_]) {
      push_new(v);
    } else if (!code_.empty()) {
      code_.push_back(std::uint8_t(last_));
    }
    ++count_;
  }
  ParamField finish() {
    if (!values_.empty()) return ParamField::from_values(std::move(values_));
    if (code_.empty()) return ParamField(palette_.empty() ? 0.0 : palette_[0]);
    return ParamField::from_palette(std::move(palette_), std::move(code_));
  }

 private:
  // v differs from the last value pushed (or is the first).
  void push_new(Real v) {
    const auto hit = std::find(palette_.begin(), palette_.end(), v);
    last_ = std::size_t(hit - palette_.begin());
    if (hit == palette_.end()) {
      if (palette_.size() == ParamField::palette_max) {
        values_.reserve(count_ + 1);
        for (std::size_t i = 0; i < count_; ++i) values_.push_back(palette_[code_[i]]);
        values_.push_back(v);
        std::vector<std::uint8_t>().swap(code_);
        return;
      }
      palette_.push_back(v);
    }
    // The second distinct value: every element so far held the first.
    if (code_.empty() && palette_.size() > 1) code_.assign(count_, 0);
    if (!code_.empty()) code_.push_back(std::uint8_t(last_));
  }

  std::vector<Real> values_;          // per-element form, once more than palette_max values were seen
  std::vector<Real> palette_;         // the distinct values so far, in order of first appearance
  std::vector<std::uint8_t> code_;    // empty while every value equals palette_[0]
  std::size_t last_ = 0;              // palette index of the last value pushed
  std::size_t count_ = 0;
};

}  // namespace clothsim
