// ContactMemory's remould displacement (contact_memory.h): the strength loss follows the
// shear a column took while it yielded. A column on its loading branch (rigidly held, up to
// its yield pressure) yields only where its block pushed with its whole capacity AND the body
// presses further into it. Checked on one block of 4 x 4 columns under a body moving along
// the soil, so that what decides is the rule, not a solve: a box sliding level over soil it
// has pressed keeps its columns' strength, a body pressing fresh soil (a wheel's front arc)
// remoulds it, and a block held below its capacity does not flow either way.
#include <gtest/gtest.h>

#include <vector>

#include "contact_memory.h"
#include "contact_solver.h"
#include "shore/terrain/material.h"

using namespace shore;
using namespace shore::bullet::contact_detail;

namespace {

constexpr int kColumns = 4;  // one block (TerrainContactSettings::block_columns)
constexpr double kCell = 0.01, kH = 1.0 / 240;

struct Pressed {
  EnvelopeRaster envelope;
  std::vector<terrain::ContactElement> elements;
  std::vector<Block> blocks;
  ContactMemory memory;
  SolverBody body;

  Pressed() {
    envelope.resize(0, 0, kColumns, kColumns, false);
    for (double& z : envelope.lower) z = 0.0;
    for (int j = 0; j < kColumns; ++j)
      for (int i = 0; i < kColumns; ++i) {
        terrain::ContactElement e;
        e.point = {(i + 0.5) * kCell, (j + 0.5) * kCell, 0.0};
        e.area = kCell * kCell;
        e.pressure = 2.0e5;  // on its loading branch: stiffness +infinity, finite yield pressure
        e.i = i, e.j = j;
        e.raster_index = static_cast<std::int32_t>(envelope.index(i, j));
        elements.push_back(e);
      }
    body.inv_mass = 1.0 / 40.0;
    body.com = {0.02, 0.02, 0.05};
  }

  /// One substep with the body moving at v, its block pushing `share` of its capacity.
  void substep(Vec3 v, double share) {
    body.v = v;
    const terrain::Material soil;
    gather_blocks(elements, std::span(&soil, 1), {}, memory.shear_length(), memory.remould_length(), kColumns, blocks);
    EXPECT_EQ(blocks.size(), 1u);
    for (Block& b : blocks) b.normal_impulse = share * b.capacity * kH;
    memory.advance(elements, envelope, body, blocks, kColumns, kH);
  }
};

}  // namespace

TEST(ContactMemoryRemould, ColumnsABodySlidesAlongAtTheirCapacityKeepTheirStrength) {
  Pressed p;
  for (int k = 0; k < 24; ++k) p.substep({0.5, 0.0, 0.0}, 1.0);
  ASSERT_EQ(p.memory.remould_length().size(), std::size_t(kColumns * kColumns));
  for (std::size_t k = 0; k < p.memory.remould_length().size(); ++k) {
    EXPECT_NEAR(p.memory.shear_length()[k], 24 * 0.5 * kH, 1e-12) << "column " << k << " is sheared";
    EXPECT_EQ(p.memory.remould_length()[k], 0.0) << "column " << k << " is not pressed further: it does not flow";
  }
}

// A box gliding on soil at its yield pressure rocks: its edges dip in and out by a few
// hundredths of its slip. That is not pressing the columns further, and they keep their
// strength; the same body pressing in at a tenth of its slip (a shallow wheel arc) flows.
TEST(ContactMemoryRemould, ColumnsABodyGlidesOverWithAShallowDipKeepTheirStrength) {
  Pressed p;
  for (int k = 0; k < 24; ++k) p.substep({0.5, 0.0, -0.01}, 1.0);
  for (std::size_t k = 0; k < p.memory.remould_length().size(); ++k) {
    EXPECT_GT(p.memory.shear_length()[k], 0.0);
    EXPECT_EQ(p.memory.remould_length()[k], 0.0) << "column " << k << " dips by a fiftieth of the slip";
  }
}

TEST(ContactMemoryRemould, ColumnsABodyPressesFurtherAtTheirCapacityRemould) {
  Pressed p;
  for (int k = 0; k < 24; ++k) p.substep({0.5, 0.0, -0.05}, 1.0);
  for (std::size_t k = 0; k < p.memory.remould_length().size(); ++k) {
    EXPECT_GT(p.memory.shear_length()[k], 0.0);
    EXPECT_EQ(p.memory.remould_length()[k], p.memory.shear_length()[k]) << "column " << k << " yields";
  }
}

TEST(ContactMemoryRemould, ABodyThatStopsPressingKeepsTheLossItTookAndAddsNone) {
  Pressed p;
  for (int k = 0; k < 12; ++k) p.substep({0.5, 0.0, -0.05}, 1.0);
  const std::vector<double> taken(p.memory.remould_length().begin(), p.memory.remould_length().end());
  for (int k = 0; k < 12; ++k) p.substep({0.5, 0.0, 0.0}, 1.0);
  for (std::size_t k = 0; k < taken.size(); ++k) {
    EXPECT_GT(taken[k], 0.0);
    EXPECT_GT(p.memory.shear_length()[k], taken[k]) << "column " << k << " is sheared further";
    EXPECT_EQ(p.memory.remould_length()[k], taken[k]) << "column " << k;
  }
}

TEST(ContactMemoryRemould, ABlockHeldBelowItsCapacityDoesNotFlowWhereTheBodyPresses) {
  Pressed p;
  for (int k = 0; k < 24; ++k) p.substep({0.5, 0.0, -0.05}, 0.6);
  for (std::size_t k = 0; k < p.memory.remould_length().size(); ++k) {
    EXPECT_GT(p.memory.shear_length()[k], 0.0);
    EXPECT_EQ(p.memory.remould_length()[k], 0.0) << "column " << k;
  }
}
