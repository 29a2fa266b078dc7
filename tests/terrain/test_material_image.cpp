// Material images: 8-bit greyscale PNG or raw indices painted onto the columns they cover,
// looking like the image from above; wrong sizes, indices beyond the palette and images that
// are not index images are refused by name, the terrain untouched; corrupt PNGs never crash.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "png_writer.h"
#include "shore/core/error.h"
#include "shore/terrain/material_image.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

/// A PNG of w x h pixels of `channels` 8-bit channels, in memory.
std::vector<unsigned char> png8(int w, int h, int channels, const std::vector<unsigned char>& px) {
  std::vector<unsigned char> out;
  const auto sink = [](void* context, void* data, int size) {
    auto* bytes = static_cast<std::vector<unsigned char>*>(context);
    const auto* p = static_cast<const unsigned char*>(data);
    bytes->insert(bytes->end(), p, p + size);
  };
  EXPECT_TRUE(stbi_write_png_to_func(sink, &out, w, h, channels, px.data(), w * channels));
  return out;
}

Terrain three_soils() {
  TerrainSettings s;
  s.threads = 1;
  Terrain t(s);
  t.set_palette({Material::sand(), Material::mud(), Material::snow()});
  return t;
}

// A 4 x 3 image: row 0 (the top, far side) 0 1 2 0; row 1 1 1 1 1; row 2 2 0 0 2.
const std::vector<unsigned char> kPixels = {0, 1, 2, 0, 1, 1, 1, 1, 2, 0, 0, 2};

void expect_painted_as_image(const Terrain& t, std::int64_t i0, std::int64_t j0) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_EQ(t.material_index(i0 + c, j0 + 2 - r), kPixels[static_cast<std::size_t>(r * 4 + c)])
          << "pixel " << c << ", " << r;
  for (int c = -1; c <= 4; ++c) {  // nothing around it
    EXPECT_EQ(t.material_index(i0 + c, j0 - 1), 0);
    EXPECT_EQ(t.material_index(i0 + c, j0 + 3), 0);
  }
}

}  // namespace

TEST(MaterialImage, PngAndRawIndicesPaintTheColumnsAsSeenFromAbove) {
  const MaterialImage png = MaterialImage::from_png_bytes(png8(4, 3, 1, kPixels), "track.png");
  ASSERT_EQ(png.width(), 4);
  ASSERT_EQ(png.rows(), 3);
  Terrain a = three_soils();
  a.paint_image(png, {10, -20, 4, 3});
  expect_painted_as_image(a, 10, -20);

  const auto file = std::filesystem::temp_directory_path() / "shore_terrain_test_track.raw";
  {
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(kPixels.data()), static_cast<std::streamsize>(kPixels.size()));
  }
  Terrain b = three_soils();
  b.paint_image(MaterialImage::from_raw(file, 4, 3), {10, -20, 4, 3});
  expect_painted_as_image(b, 10, -20);
  EXPECT_EQ(b.state_hash(), a.state_hash());
  std::filesystem::remove(file);
}

TEST(MaterialImage, WrongSizesAndIndicesBeyondThePaletteAreRefusedByName) {
  Terrain t = three_soils();
  t.paint_rect({0, 0, 2, 2}, 2);
  const std::uint64_t before = t.state_hash();
  const MaterialImage good = MaterialImage::from_png_bytes(png8(4, 3, 1, kPixels), "track.png");
  std::string m = message_of<shore::InvalidSetting>([&] { t.paint_image(good, {0, 0, 3, 4}); });
  EXPECT_NE(m.find("paint_image(track.png).rect.nx x ny = 3 x 4"), std::string::npos) << m;
  EXPECT_NE(m.find("4 x 3 pixels"), std::string::npos) << m;

  std::vector<unsigned char> beyond = kPixels;
  beyond[6] = 9;  // pixel (2, 1)
  const MaterialImage bad = MaterialImage::from_png_bytes(png8(4, 3, 1, beyond), "bad.png");
  m = message_of<shore::InvalidSetting>([&] { t.paint_image(bad, {0, 0, 4, 3}); });
  EXPECT_NE(m.find("paint_image(bad.png).pixel(2, 1) = 9"), std::string::npos) << m;
  EXPECT_NE(m.find("[0, 2]"), std::string::npos) << m;
  EXPECT_EQ(t.state_hash(), before);

  m = message_of<shore::FileError>([&] { (void)MaterialImage::from_raw_bytes(kPixels, "short.raw", 5, 3); });
  EXPECT_NE(m.find("short.raw"), std::string::npos) << m;
  EXPECT_NE(m.find("size is 12 bytes, expected 15"), std::string::npos) << m;

  std::vector<unsigned char> rgb;
  for (unsigned char p : kPixels) rgb.insert(rgb.end(), {p, p, p});
  m = message_of<shore::FileError>([&] { (void)MaterialImage::from_png_bytes(png8(4, 3, 3, rgb), "rgb.png"); });
  EXPECT_NE(m.find("rgb.png: 3 channels"), std::string::npos) << m;
  m = message_of<shore::FileError>([&] {
    (void)MaterialImage::from_png_bytes(shore::fuzz::png16(2, 2, {0, 1, 2, 3}), "deep.png");
  });
  EXPECT_NE(m.find("deep.png: 16-bit"), std::string::npos) << m;
  m = message_of<shore::FileError>([&] { (void)MaterialImage::from_png(std::filesystem::path("/nonexistent.png")); });
  EXPECT_NE(m.find("/nonexistent.png"), std::string::npos) << m;
}

TEST(MaterialImage, CorruptPngsGiveAnErrorOrAnImageNeverACrash) {
  // Every byte of a small index PNG set to three other values: each copy loads or is
  // refused with a FileError (the loaders share the heightmap's chunk and size checks).
  const std::vector<unsigned char> good = png8(4, 3, 1, kPixels);
  int refused = 0, loaded = 0;
  for (std::size_t k = 0; k < good.size(); ++k)
    for (unsigned char v : {0x00, 0x7f, 0xff}) {
      if (good[k] == v) continue;
      std::vector<unsigned char> bytes = good;
      bytes[k] = v;
      try {
        const MaterialImage image = MaterialImage::from_png_bytes(bytes, "flipped.png");
        EXPECT_EQ(static_cast<std::size_t>(image.width()) * static_cast<std::size_t>(image.rows()), 12u);
        ++loaded;
      } catch (const shore::FileError&) {
        ++refused;
      }
    }
  EXPECT_GT(refused, 0);
  std::printf("[ corrupt ] %d copies refused, %d loaded (bytes outside checked fields)\n", refused, loaded);
}
