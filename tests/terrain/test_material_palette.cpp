// Palette files: presets with fields overridden, one line per index; a palette file and an
// index image together make a map whose plates sink by each entry's Bekker law; bad lines are
// refused naming the file, the line and the problem.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "shore/core/error.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/material_image.h"
#include "shore/terrain/material_palette.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

const char* const kTrack = R"(# a test track
0 sand
1 mud   bekker_kphi=1.5e6 alpha=0.3   # wetter than Wong's
2 sand  name=gravel bekker_kphi=6e6 theta_out=0.6 spray.adhesion=0 rigid=0

)";

std::string palette_error(const std::string& text) {
  return message_of<shore::FileError>([&] { (void)parse_palette(text, "bad.palette"); });
}

}  // namespace

TEST(MaterialPalette, PresetsWithFieldsOverriddenOneLinePerIndex) {
  const std::vector<Material> p = parse_palette(kTrack, "track.palette");
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0].name, "sand");
  EXPECT_EQ(p[0].bekker_kphi, Material::sand().bekker_kphi);
  EXPECT_EQ(p[1].name, "mud");
  EXPECT_EQ(p[1].bekker_kphi, 1.5e6);
  EXPECT_EQ(p[1].alpha, 0.3);
  EXPECT_EQ(p[1].bekker_n, Material::mud().bekker_n);  // the rest is the preset's
  EXPECT_EQ(p[2].name, "gravel");
  EXPECT_EQ(p[2].bekker_kphi, 6e6);
  EXPECT_EQ(p[2].theta_out, 0.6);
  EXPECT_EQ(p[2].spray.adhesion, 0.0);
  EXPECT_FALSE(p[2].rigid);
}

TEST(MaterialPalette, AFileAndAnImageMakeAMapThatBearsByEachEntry) {
  const auto file = std::filesystem::temp_directory_path() / "shore_terrain_test_track.palette";
  {
    std::ofstream out(file);
    out << kTrack;
  }
  const std::vector<Material> palette = read_palette(file);
  std::filesystem::remove(file);
  TerrainSettings s;
  s.threads = 1;
  s.material = palette[0];
  Terrain t(s);
  t.set_palette(palette);
  // 3 x 1 pixels, each painting a 40 x 40 column square: left mud, middle sand, right gravel.
  std::vector<std::uint8_t> index;
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 120; ++c) index.push_back(c < 40 ? 1 : (c < 80 ? 0 : 2));
  t.paint_image(MaterialImage(120, 40, index, "three squares"), {-60, -20, 120, 40});
  const double p = 40e3;
  for (int k = 0; k < 3; ++k) {
    const std::int64_t i0 = -55 + 40 * k;  // a 0.3 m plate in the middle of square k
    double depth = 0.0;
    for (int step = 1; step <= 20; ++step) {
      depth += t.bearing_offset(box_envelope(i0, -15, 30, 30, -depth), p * 0.09 * step / 20);
      const shore::EnvelopeRaster env = box_envelope(i0, -15, 30, 30, -depth);
      const Imprint im{&env};
      t.step({&im, 1});
    }
    const Material& m = palette[k == 0 ? 1 : (k == 1 ? 0 : 2)];
    EXPECT_EQ(t.material_at(i0 + 15, 0).name, m.name);
    const double ref = bekker::plate_sinkage(m, 0.3, p);
    EXPECT_NEAR(depth, ref, 0.02 * ref) << m.name;
  }
}

TEST(MaterialPalette, BadLinesAreRefusedNamingTheFileAndTheLine) {
  std::string m = palette_error("0 sand\n1 clay\n");
  EXPECT_NE(m.find("palette bad.palette, line 2: unknown preset \"clay\""), std::string::npos) << m;
  m = palette_error("0 sand\n# comment\n\n1 mud bekker_k=3\n");
  EXPECT_NE(m.find("line 4: unknown field \"bekker_k\""), std::string::npos) << m;
  m = palette_error("0 sand alpha=lots\n");
  EXPECT_NE(m.find("line 1: alpha = \"lots\" is not a number"), std::string::npos) << m;
  m = palette_error("0 sand\n2 mud\n");
  EXPECT_NE(m.find("line 2: index \"2\" where 1 was expected"), std::string::npos) << m;
  m = palette_error("0 sand\n1 mud bekker_n=5\n");
  EXPECT_NE(m.find("line 2: terrain.Material(mud).bekker_n = 5: must be in (0, 3)"), std::string::npos) << m;
  m = palette_error("0 sand rigid=2\n");
  EXPECT_NE(m.find("rigid = 2 must be 0 or 1"), std::string::npos) << m;
  m = palette_error("0 sand alpha\n");
  EXPECT_NE(m.find("\"alpha\" is not field=value"), std::string::npos) << m;
  m = palette_error("# nothing\n");
  EXPECT_NE(m.find("palette bad.palette: no materials"), std::string::npos) << m;
  std::string many;
  for (int k = 0; k <= 256; ++k) many += std::to_string(k) + " sand\n";
  m = palette_error(many);
  EXPECT_NE(m.find("line 257: more than 256 materials"), std::string::npos) << m;
  m = message_of<shore::FileError>([] { (void)read_palette("/nonexistent.palette"); });
  EXPECT_NE(m.find("/nonexistent.palette"), std::string::npos) << m;
}
