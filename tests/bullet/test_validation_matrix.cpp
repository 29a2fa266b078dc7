// A sample of the validation matrix (scenes/validation_matrix.h; the whole of it is
// shore-bench --only matrix): one case per family on two of Wong's soils (dry sand and
// LETE sand; the slope box on dry sand and snow, where it holds as Coulomb says: the boxes
// that should slide trip, docs/terrain.md, "Validation matrix"), each cell within its
// tolerance of its outside reference (Bekker, Wong-Reece, Coulomb, the energy balance).
#include <gtest/gtest.h>

#include <string>

#include "shore/scenes/validation_matrix.h"

namespace {

using shore::scenes::MatrixCase;
using shore::scenes::MatrixCell;

/// The matrix's case of this soil and family whose label starts with `label`.
MatrixCase find_case(const std::string& soil, const std::string& family, const std::string& label) {
  const auto soils = shore::scenes::matrix_soils();
  for (const MatrixCase& c : shore::scenes::matrix_cases(false))
    if (soils[c.soil].name == soil && c.family == family && c.label.rfind(label, 0) == 0) return c;
  ADD_FAILURE() << "no matrix case " << soil << ", " << family << " " << label;
  return {};
}

struct Sample {
  const char* soil;
  const char* family;
  const char* label;
};

class ValidationMatrixSample : public ::testing::TestWithParam<Sample> {};

TEST_P(ValidationMatrixSample, EveryCellWithinItsTolerance) {
  const Sample s = GetParam();
  const MatrixCase c = find_case(s.soil, s.family, s.label);
  if (c.family.empty()) return;
  const auto cells = shore::scenes::run_matrix_case(c);
  ASSERT_FALSE(cells.empty());
  for (const MatrixCell& m : cells) {
    EXPECT_TRUE(m.outside_validity.empty()) << m.quantity << ": sampled cells lie inside the references' validity";
    EXPECT_LE(std::abs(m.error), m.tolerance)
        << m.soil << ", " << m.family << " " << m.label << ", " << m.quantity << ": measured " << m.measured
        << ", reference " << m.reference << ", error " << m.error << " (" << m.error_kind << ")";
  }
}

INSTANTIATE_TEST_SUITE_P(
    TwoSoils, ValidationMatrixSample,
    ::testing::Values(Sample{"dry sand", "plate", "0.2 m, 60 kPa"}, Sample{"dry sand", "wheel static", "D 0.8 m, 2 kN"},
                      Sample{"dry sand", "wheel towed", "D 0.8 m, 2 kN"},
                      Sample{"dry sand", "driven wheel", "slip 0.2"}, Sample{"dry sand", "slope box", "phi - 7"},
                      Sample{"dry sand", "sphere drop", "D 0.2 m"}, Sample{"LETE sand", "plate", "0.4 m, 500 kPa"},
                      Sample{"LETE sand", "wheel static", "D 0.5 m, 25 kN"},
                      Sample{"LETE sand", "wheel towed", "D 0.8 m, 25 kN"},
                      Sample{"LETE sand", "driven wheel", "slip 0.5"}, Sample{"snow", "slope box", "phi + 12"},
                      Sample{"LETE sand", "sphere drop", "D 0.2 m"}));

}  // namespace
