// shore::terrain::Terrain's material map: the palette and the painting of palette indices
// onto columns (one byte per column, kept in the tiles; terrain.h says what reads them).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "region.h"
#include "shore/core/error.h"
#include "terrain_impl.h"

namespace shore::terrain {

namespace {

void check_index(int index, std::size_t palette_size, const std::string& where) {
  if (index < 0 || static_cast<std::size_t>(index) >= palette_size)
    throw InvalidSetting(where + ".index", std::to_string(index),
                         "must be a palette entry, in [0, " + std::to_string(palette_size - 1) + "]");
}

// Painting a rectangle creates its tiles (a painted column differs from the untouched
// ground): beyond one region's worth of columns it is a mistake, refused before any change.
void check_rect(const GridRect& rect, const std::string& where) {
  const Check c{where + ".rect"};
  c.at_least("nx", rect.nx, 0);
  c.at_least("ny", rect.ny, 0);
  if (static_cast<std::int64_t>(rect.nx) * rect.ny > kMaxRegionColumns)
    throw InvalidSetting(c.name("nx * ny"), detail::to_text(static_cast<std::int64_t>(rect.nx) * rect.ny),
                         "must be at most " + detail::to_text(kMaxRegionColumns));
}

/// Writes `index` to the columns of `rect` whose entry in `mask` (row-major over rect, or
/// empty: all) is set, stamping the tiles it writes with the current generation (call
/// advance_generation first). Index 0 needs no tile where there is none (the default map).
void paint(TileStore& store, const GridRect& rect, std::span<const unsigned char> mask, int index) {
  const auto value = static_cast<std::uint8_t>(index);
  const auto write = [&](Tile& t, const TileRun& run) {
    const std::size_t row = static_cast<std::size_t>(run.y) * static_cast<std::size_t>(rect.nx) + run.x;
    if (t.material.empty()) {
      if (value == 0) return;
      // A run the mask leaves out gives its tile no map: a map of all 0 would count in the
      // hash and the file, yet read back as no map.
      bool any = mask.empty();
      for (int k = 0; k < run.count && !any; ++k) any = mask[row + k] != 0;
      if (!any) return;
      t.material.assign(t.height.size(), 0);
    }
    for (int k = 0; k < run.count; ++k)
      if (mask.empty() || mask[row + k]) t.material[run.local + k] = value;
    if (value == 0) t.normalize_material();
    store.mark_painted(t);
  };
  if (value == 0)
    store.for_each_existing_run(rect, write);
  else
    store.for_each_run_creating(rect, write);
}

void check_layer(int lower_index, double depth, std::size_t palette_size, const std::string& where) {
  if (lower_index < 0 || static_cast<std::size_t>(lower_index) >= palette_size)
    throw InvalidSetting(where + ".lower_index", std::to_string(lower_index),
                         "must be a palette entry, in [0, " + std::to_string(palette_size - 1) + "]");
  Check{where}.in_closed("depth", depth, 0.0, 1e6);
}

/// Gives the columns of `rect` whose entry in `mask` is set (empty: all) a lower layer of
/// `lower` whose crust ends `depth` below their present top (at sinkage max(0, sinkage) +
/// depth), stamping the tiles with the current generation.
void paint_layer(TileStore& store, const GridRect& rect, std::span<const unsigned char> mask, int lower, double depth) {
  const auto value = static_cast<std::uint8_t>(lower);
  store.for_each_run_creating(rect, [&](Tile& t, const TileRun& run) {
    const std::size_t row = static_cast<std::size_t>(run.y) * static_cast<std::size_t>(rect.nx) + run.x;
    bool any = mask.empty();
    for (int k = 0; k < run.count && !any; ++k) any = mask[row + k] != 0;
    if (!any) return;
    if (!t.layered()) {
      t.layer_boundary.assign(t.height.size(), kNoLayer);
      t.layer_lower.assign(t.height.size(), 0);
    }
    for (int k = 0; k < run.count; ++k) {
      if (!mask.empty() && !mask[row + k]) continue;
      const std::size_t c = run.local + static_cast<std::size_t>(k);
      t.layer_boundary[c] = std::max(0.0, t.sinkage[c]) + depth;
      t.layer_lower[c] = value;
    }
    store.mark_painted(t);
  });
  store.mark_layered();
}

/// The columns of a disc (centres within radius of (x, y)) as a rectangle and its mask.
std::pair<GridRect, std::vector<unsigned char>> disc_mask(const Terrain& terrain, double x, double y, double radius,
                                                          const std::string& where) {
  const Check c{where};
  c.in_closed("x", x, -1e12, 1e12);
  c.in_closed("y", y, -1e12, 1e12);
  c.in_closed("radius", radius, 0.0, 1e12);
  const TerrainSettings& s = terrain.settings();
  // Every column whose centre can lie within the radius, then the exact test per column.
  const auto first_i = static_cast<std::int64_t>(std::floor((x - radius - s.origin_x) / s.cell));
  const auto last_i = static_cast<std::int64_t>(std::ceil((x + radius - s.origin_x) / s.cell));
  const auto first_j = static_cast<std::int64_t>(std::floor((y - radius - s.origin_y) / s.cell));
  const auto last_j = static_cast<std::int64_t>(std::ceil((y + radius - s.origin_y) / s.cell));
  const std::int64_t nx = last_i - first_i + 1, ny = last_j - first_j + 1;  // each at most 2e16: no overflow
  if (nx > kMaxRegionColumns || ny > kMaxRegionColumns || nx * ny > kMaxRegionColumns)
    throw InvalidSetting(c.name("radius"), detail::to_text(radius),
                         "must cover at most " + detail::to_text(kMaxRegionColumns) + " columns");
  const GridRect rect = GridRect::spanning(first_i, first_j, last_i, last_j);
  std::vector<unsigned char> mask(rect.size());
  for (std::int64_t j = first_j; j <= last_j; ++j)
    for (std::int64_t i = first_i; i <= last_i; ++i) {
      const double dx = terrain.column_x(i) - x, dy = terrain.column_y(j) - y;
      mask[rect.index(i, j)] = dx * dx + dy * dy <= radius * radius ? 1 : 0;
    }
  return {rect, std::move(mask)};
}

/// The mask of a predicate over a rectangle's column centres, whole before anything is
/// painted: a predicate that throws leaves the map untouched.
std::vector<unsigned char> where_mask(const Terrain& terrain, const GridRect& rect,
                                      const std::function<bool(double x, double y)>& inside, const std::string& where) {
  if (!inside) throw InvalidSetting(where + ".inside", "empty", "must be a callable predicate");
  std::vector<unsigned char> mask(rect.size());
  for (std::int64_t j = rect.j0; j < rect.j1(); ++j)
    for (std::int64_t i = rect.i0; i < rect.i1(); ++i)
      mask[rect.index(i, j)] = inside(terrain.column_x(i), terrain.column_y(j)) ? 1 : 0;
  return mask;
}

}  // namespace

std::span<const Material> Terrain::palette() const noexcept { return impl_->palette; }

void Terrain::Impl::check_palette(std::span<const Material> candidate, const std::string& where) const {
  if (candidate.empty() || candidate.size() > static_cast<std::size_t>(kMaxMaterials))
    throw InvalidSetting(where + ".size()", std::to_string(candidate.size()),
                         "must be in [1, " + std::to_string(kMaxMaterials) + "]");
  const Material& now = s.material;
  for (std::size_t k = 0; k < candidate.size(); ++k) {
    const Material& m = candidate[k];
    const std::string entry = where + "[" + std::to_string(k) + "]";
    try {
      m.validate();
    } catch (const InvalidSetting& e) {
      throw InvalidSetting(entry, m.name, e.what());
    }
    if (m.soil_depth != now.soil_depth)
      throw InvalidSetting(entry + ".soil_depth", detail::to_text(m.soil_depth),
                           "must equal the present soil_depth (" + detail::to_text(now.soil_depth) + " m)");
    // Rigid columns (a road, a rock) on deforming ground, never soft ones on rigid ground
    // (which never steps); entry 0 is the ground's own material.
    if (m.rigid != now.rigid && (k == 0 || now.rigid))
      throw InvalidSetting(entry + ".rigid", m.rigid ? "true" : "false",
                           std::string("must equal the present rigid flag (") + (now.rigid ? "true" : "false") +
                               (now.rigid ? ")" : "; only entries after 0 may be rigid on deforming ground)"));
  }
}

void Terrain::Impl::adopt_palette(std::vector<Material> checked) {
  s.material = checked[0];
  palette = std::move(checked);
  palette_at = tiles.generation();
}

void Terrain::set_palette(std::vector<Material> palette) {
  const std::string where = "terrain.Terrain.set_palette";
  impl_->check_palette(palette, where);
  if (const int largest = impl_->tiles.largest_material(); static_cast<std::size_t>(largest) >= palette.size())
    throw InvalidSetting(where + ".size()", std::to_string(palette.size()),
                         "must be more than the largest index painted on the map (" + std::to_string(largest) + ")");
  impl_->tiles.advance_generation();  // a soil delta sends the palette set in this generation
  impl_->adopt_palette(std::move(palette));
}

int Terrain::material_index(std::int64_t i, std::int64_t j) const { return impl_->tiles.material_at(i, j); }

const Material& Terrain::material_at(std::int64_t i, std::int64_t j) const {
  return impl_->palette[impl_->tiles.material_at(i, j)];
}

void Terrain::material_indices(const GridRect& rect, std::span<std::uint8_t> out) const {
  if (rect.nx < 0 || rect.ny < 0 || out.size() != static_cast<std::size_t>(rect.nx) * static_cast<std::size_t>(rect.ny))
    throw InvalidSetting("terrain.Terrain.material_indices(out).size", detail::to_text(out.size()),
                         "must be nx * ny of the rectangle");
  impl_->tiles.for_each_run(rect, [&](const Tile* t, const TileRun& run) {
    std::uint8_t* dst = out.data() + static_cast<std::size_t>(run.y) * static_cast<std::size_t>(rect.nx) + run.x;
    if (t == nullptr || t->material.empty())
      std::fill_n(dst, run.count, std::uint8_t{0});
    else
      std::copy_n(t->material.data() + run.local, run.count, dst);
  });
}

std::vector<GridRect> Terrain::painted_since(std::uint64_t g) const {
  const int n = impl_->tiles.n();
  std::vector<GridRect> rects;
  for (const TileKey& key : impl_->tiles.painted_since(g)) rects.push_back({key.tx * n, key.ty * n, n, n});
  return rects;
}

void Terrain::paint_rect(const GridRect& rect, int index) {
  const std::string where = "terrain.Terrain.paint_rect";
  check_index(index, impl_->palette.size(), where);
  check_rect(rect, where);
  impl_->tiles.advance_generation();
  paint(impl_->tiles, rect, {}, index);
}

void Terrain::paint_disc(double x, double y, double radius, int index) {
  const std::string where = "terrain.Terrain.paint_disc";
  check_index(index, impl_->palette.size(), where);
  const auto [rect, mask] = disc_mask(*this, x, y, radius, where);
  impl_->tiles.advance_generation();
  paint(impl_->tiles, rect, mask, index);
}

void Terrain::paint_where(const GridRect& rect, const std::function<bool(double x, double y)>& inside, int index) {
  const std::string where = "terrain.Terrain.paint_where";
  check_index(index, impl_->palette.size(), where);
  check_rect(rect, where);
  const std::vector<unsigned char> mask = where_mask(*this, rect, inside, where);
  impl_->tiles.advance_generation();
  paint(impl_->tiles, rect, mask, index);
}

void Terrain::paint_image(const MaterialImage& image, const GridRect& rect) {
  const std::string where = "terrain.Terrain.paint_image(" + image.name() + ")";
  if (rect.nx != image.width() || rect.ny != image.rows())
    throw InvalidSetting(
        where + ".rect.nx x ny", std::to_string(rect.nx) + " x " + std::to_string(rect.ny),
        "must equal the image's " + std::to_string(image.width()) + " x " + std::to_string(image.rows()) + " pixels");
  check_rect(rect, where);
  // Checked whole before painting: a bad pixel leaves the map untouched.
  const std::size_t size = impl_->palette.size();
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.width(); ++c)
      if (image.at(c, r) >= size)
        throw InvalidSetting(where + ".pixel(" + std::to_string(c) + ", " + std::to_string(r) + ")",
                             std::to_string(image.at(c, r)),
                             "must be a palette entry, in [0, " + std::to_string(size - 1) + "]");
  // One pass per index present: paint() writes one index through a mask.
  std::vector<unsigned char> mask(rect.size());
  bool present[Terrain::kMaxMaterials] = {};
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.width(); ++c) present[image.at(c, r)] = true;
  impl_->tiles.advance_generation();
  for (int index = 0; index < Terrain::kMaxMaterials; ++index) {
    if (!present[index]) continue;
    for (int r = 0; r < image.rows(); ++r) {
      const std::size_t row = static_cast<std::size_t>(image.rows() - 1 - r) * static_cast<std::size_t>(rect.nx);
      for (int c = 0; c < image.width(); ++c) mask[row + c] = image.at(c, r) == index ? 1 : 0;
    }
    paint(impl_->tiles, rect, mask, index);
  }
}

void Terrain::paint_layer_rect(const GridRect& rect, int lower_index, double depth) {
  const std::string where = "terrain.Terrain.paint_layer_rect";
  check_layer(lower_index, depth, impl_->palette.size(), where);
  check_rect(rect, where);
  impl_->tiles.advance_generation();
  paint_layer(impl_->tiles, rect, {}, lower_index, depth);
}

void Terrain::paint_layer_disc(double x, double y, double radius, int lower_index, double depth) {
  const std::string where = "terrain.Terrain.paint_layer_disc";
  check_layer(lower_index, depth, impl_->palette.size(), where);
  const auto [rect, mask] = disc_mask(*this, x, y, radius, where);
  impl_->tiles.advance_generation();
  paint_layer(impl_->tiles, rect, mask, lower_index, depth);
}

void Terrain::paint_layer_where(const GridRect& rect, const std::function<bool(double x, double y)>& inside,
                                int lower_index, double depth) {
  const std::string where = "terrain.Terrain.paint_layer_where";
  check_layer(lower_index, depth, impl_->palette.size(), where);
  check_rect(rect, where);
  const std::vector<unsigned char> mask = where_mask(*this, rect, inside, where);
  impl_->tiles.advance_generation();
  paint_layer(impl_->tiles, rect, mask, lower_index, depth);
}

void Terrain::clear_layers(const GridRect& rect) {
  const std::string where = "terrain.Terrain.clear_layers";
  check_rect(rect, where);
  impl_->tiles.advance_generation();
  impl_->tiles.for_each_existing_run(rect, [&](Tile& t, const TileRun& run) {
    if (!t.layered()) return;
    std::fill_n(t.layer_boundary.begin() + static_cast<std::ptrdiff_t>(run.local), run.count, kNoLayer);
    t.normalize_layers();
    impl_->tiles.mark_painted(t);
  });
}

int Terrain::lower_index(std::int64_t i, std::int64_t j) const {
  const ColumnLayer layer = impl_->tiles.layer_at(i, j);
  return layer.layered() ? layer.lower : -1;
}

double Terrain::layer_boundary(std::int64_t i, std::int64_t j) const { return impl_->tiles.layer_at(i, j).boundary; }

int Terrain::exposed_index(std::int64_t i, std::int64_t j) const {
  const std::uint8_t upper = impl_->tiles.material_at(i, j);
  if (!impl_->tiles.layered()) return upper;
  return impl_->tiles.layer_at(i, j).exposed(upper, sinkage(i, j));
}

const Material& Terrain::exposed_material(std::int64_t i, std::int64_t j) const {
  return impl_->palette[static_cast<std::size_t>(exposed_index(i, j))];
}

}  // namespace shore::terrain
