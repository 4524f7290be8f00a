// ParamField's three forms and the builder that picks the cheapest: every element reads back exactly the value
// pushed, and the bytes held are those of the form (one scalar; a palette and a byte an element; 8 bytes an
// element).
#include <doctest/doctest.h>

#include <vector>

#include "core/param_field.h"

using namespace clothsim;

namespace {

ParamField build(const std::vector<Real>& values) {
  ParamFieldBuilder b;
  for (Real v : values) b.push(v);
  return b.finish();
}

void check_reads_back(const ParamField& f, const std::vector<Real>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    CAPTURE(i);
    REQUIRE(f[i] == values[i]);
  }
}

}  // namespace

TEST_CASE("one value pushed many times stays one scalar") {
  const ParamField f = build(std::vector<Real>(1000, 2.5));
  CHECK(f.uniform());
  CHECK_FALSE(f.paletted());
  CHECK(f[999] == 2.5);
  CHECK(f.bytes() == sizeof(Real));
  CHECK(build({}).uniform());
  CHECK(build({})[0] == 0.0);
}

TEST_CASE("a few distinct values become a palette and one code byte per element") {
  // A Provot grid's stiffness with a bend scale: a long uniform start, then three values in turn.
  std::vector<Real> values(100, 1000.0);
  for (int i = 0; i < 900; ++i) values.push_back(i % 3 == 0 ? 1000.0 : i % 3 == 1 ? 500.0 : 100.0);
  const ParamField f = build(values);
  CHECK_FALSE(f.uniform());
  REQUIRE(f.paletted());
  CHECK(f.size() == 3);  // palette entries, in order of first appearance
  CHECK(f.data()[0] == 1000.0);
  CHECK(f.data()[1] == 500.0);
  CHECK(f.data()[2] == 100.0);
  check_reads_back(f, values);
  CHECK(f.bytes() == 3 * sizeof(Real) + 1000);
}

TEST_CASE("the value after palette_max distinct ones turns the field into a per-element array") {
  std::vector<Real> values;
  for (std::size_t i = 0; i < 3 * ParamField::palette_max; ++i) values.push_back(Real(i % ParamField::palette_max));
  const ParamField at_max = build(values);
  REQUIRE(at_max.paletted());
  CHECK(at_max.size() == ParamField::palette_max);
  check_reads_back(at_max, values);

  values.push_back(-1.0);  // one more distinct value
  values.push_back(3.0);
  const ParamField over = build(values);
  CHECK_FALSE(over.uniform());
  CHECK_FALSE(over.paletted());
  CHECK(over.stride() == 1);
  check_reads_back(over, values);
  CHECK(over.bytes() == values.size() * sizeof(Real));
}

TEST_CASE("from_values keeps one scalar or one value per element") {
  CHECK(ParamField::from_values({4.0, 4.0}).uniform());
  const ParamField f = ParamField::from_values({4.0, 5.0, 4.0});
  CHECK_FALSE(f.paletted());
  CHECK(f.stride() == 1);
  CHECK(f[2] == 4.0);
}
