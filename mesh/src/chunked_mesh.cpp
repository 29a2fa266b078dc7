// shore::mesh::ChunkedMesh: settings, the update's order of work, and merge().
#include "shore/mesh/chunked_mesh.h"

#include <algorithm>

#include "impl.h"
#include "shore/core/det_math.h"
#include "shore/core/error.h"

namespace shore::mesh {

namespace {

constexpr std::int64_t kMaxRoot = std::int64_t{1} << 28;  // cells per side (the keys' range)

bool power_of_two(std::int64_t v) { return v > 0 && (v & (v - 1)) == 0; }

}  // namespace

void MeshSettings::validate() const {
  const Check c{"mesh.MeshSettings"};
  c.non_negative("max_error", max_error);
  c.positive("max_error_pixels", max_error_pixels);
  c.in_closed("chunk_cells", chunk_cells, 4, 1024);
  if (!power_of_two(chunk_cells))
    throw InvalidSetting(c.name("chunk_cells"), shore::detail::to_text(chunk_cells),
                         "must be a power of two in [4, 1024]");
  c.in_closed("distance_steps_per_octave", distance_steps_per_octave, 1, 64);
}

void Camera::validate() const {
  const Check c{"mesh.Camera"};
  c.finite("position.x", position.x);
  c.finite("position.y", position.y);
  c.finite("position.z", position.z);
  if (!(fov_y_deg > 0.0 && fov_y_deg < 180.0))
    throw InvalidSetting(c.name("fov_y_deg"), shore::detail::to_text(fov_y_deg), "must be in (0, 180)");
  c.at_least("viewport_height", viewport_height, 1);
}

double Camera::pixels_per_radian() const {
  const double half = 0.5 * fov_y_deg * (det::detail::kPi / 180.0);
  return 0.5 * static_cast<double>(viewport_height) / det::tan(half);
}

ChunkedMesh::Impl::Impl(MeshSettings settings) : s(settings) {
  s.validate();
  for (int k = 0; k < s.distance_steps_per_octave; ++k)
    distance_steps.push_back(0.5 * det::pow(2.0, static_cast<double>(k) / s.distance_steps_per_octave));
}

void ChunkedMesh::Impl::initialise(const Field& f) {
  const Check c{"mesh.Field"};
  c.at_least("ni", f.ni(), std::int64_t{2});
  c.at_least("nj", f.nj(), std::int64_t{2});
  dom = {f.ni(), f.nj()};
  height_field = f.height_field();
  base = f.base();
  C = s.chunk_cells;
  chunk_log = 0;
  while ((std::int64_t{1} << chunk_log) < C) ++chunk_log;
  S = C;
  while (S < std::max(dom.ni - 1, dom.nj - 1)) S *= 2;
  if (S > kMaxRoot)
    throw InvalidSetting(c.name("ni"), shore::detail::to_text(std::max(dom.ni, dom.nj)),
                         "the grid may have at most 2^28 + 1 nodes along a side");
  initialised = true;
}

detail::ChunkData* ChunkedMesh::Impl::chunk_data(std::uint64_t index) const {
  if (recent_index[0] == index) return recent_data[0];
  if (recent_index[1] == index) {
    std::swap(recent_index[0], recent_index[1]);
    std::swap(recent_data[0], recent_data[1]);
    return recent_data[0];
  }
  const auto it = data.find(index);
  recent_index[1] = recent_index[0], recent_data[1] = recent_data[0];
  recent_index[0] = index;
  recent_data[0] = it == data.end() ? nullptr : const_cast<detail::ChunkData*>(&it->second);
  return recent_data[0];
}

void ChunkedMesh::Impl::allocate(std::uint64_t index) {
  const auto [it, fresh] = data.try_emplace(index);
  if (!fresh) return;
  recent_index = {~0ull, ~0ull};
  const std::size_t n = static_cast<std::size_t>((C + 1) * (C + 1));
  it->second.e[0].assign(n, 0.0f);
  it->second.e[1].assign(n, 0.0f);
  it->second.f.assign(n, 0.0f);
  it->second.queued.assign(n, 0u);
}

void ChunkedMesh::Impl::apply_changes(const std::vector<GridRect>& rects,
                                      std::map<std::uint64_t, GridRect>& error_dirty) {
  const std::int64_t chunks_per_side = S / C;
  // The chunks whose closed square meets [i_lo, i_hi] x [j_lo, j_hi].
  auto each_chunk = [&](std::int64_t i_lo, std::int64_t j_lo, std::int64_t i_hi, std::int64_t j_hi, auto&& fn) {
    const std::int64_t cx0 = std::max<std::int64_t>(0, (i_lo + C - 1) / C - 1),
                       cx1 = std::min(chunks_per_side - 1, i_hi / C);
    const std::int64_t cy0 = std::max<std::int64_t>(0, (j_lo + C - 1) / C - 1),
                       cy1 = std::min(chunks_per_side - 1, j_hi / C);
    for (std::int64_t cy = cy0; cy <= cy1; ++cy)
      for (std::int64_t cx = cx0; cx <= cx1; ++cx) fn(cx, cy);
  };
  for (const GridRect& raw : rects) {
    const std::int64_t i_lo = std::max<std::int64_t>(raw.i0, 0), j_lo = std::max<std::int64_t>(raw.j0, 0);
    const std::int64_t i_hi = std::min(raw.i0 + raw.nx, dom.ni) - 1, j_hi = std::min(raw.j0 + raw.ny, dom.nj) - 1;
    if (i_hi < i_lo || j_hi < j_lo) continue;
    each_chunk(i_lo, j_lo, i_hi, j_hi, [&](std::int64_t cx, std::int64_t cy) {
      const std::uint64_t index = chunk_index(cx, cy);
      const detail::Node o{cx * C, cy * C};
      const GridRect part = GridRect::spanning(std::max(i_lo, o.i), std::max(j_lo, o.j), std::min(i_hi, o.i + C),
                                               std::min(j_hi, o.j + C));
      auto [it, fresh] = error_dirty.try_emplace(index, part);
      if (!fresh) {
        GridRect& r = it->second;
        r = GridRect::spanning(std::min(r.i0, part.i0), std::min(r.j0, part.j0), std::max(r.i1(), part.i1()) - 1,
                               std::max(r.j1(), part.j1()) - 1);
      }
      // A chunk with detail, and its neighbours (saturation crosses chunk sides), keep errors.
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dx = -1; dx <= 1; ++dx)
          if (cx + dx >= 0 && cy + dy >= 0 && cx + dx < chunks_per_side && cy + dy < chunks_per_side)
            allocate(chunk_index(cx + dx, cy + dy));
      detail::ChunkData& cd = data.at(index);
      if (!cd.detailed) {
        cd.detailed = true;
        for (std::int64_t side = 2 * C; side <= S; side *= 2)
          ++detailed_count[square_key({o.i / side * side, o.j / side * side}, side)];
      }
    });
    // Normals read the neighbours: one node more changes what the chunks around show.
    const std::int64_t gi0 = std::max<std::int64_t>(i_lo - 1, 0), gj0 = std::max<std::int64_t>(j_lo - 1, 0);
    const std::int64_t gi1 = std::min(i_hi + 1, dom.ni - 1), gj1 = std::min(j_hi + 1, dom.nj - 1);
    dirty_output.push_back(GridRect::spanning(gi0, gj0, gi1, gj1));
    each_chunk(gi0, gj0, gi1, gj1,
               [&](std::int64_t cx, std::int64_t cy) { dirty_output_chunks.insert(chunk_index(cx, cy)); });
  }
}

const detail::Block& ChunkedMesh::Impl::chunk_block(std::uint64_t index) {
  const auto it = blocks.find(index);
  if (it != blocks.end()) return it->second;
  const Node o = chunk_origin(index);
  Block& b = blocks[index];
  b.read(*field, dom, GridRect{o.i, o.j, static_cast<int>(C) + 1, static_cast<int>(C) + 1}.grown(1), &nodes_read);
  return b;
}

detail::Vec3 ChunkedMesh::Impl::node_position(Node n) {
  const auto [it, fresh] = node_positions.try_emplace(node_key(n));
  if (fresh) {
    Block b;
    b.read(*field, dom, {n.i, n.j, 1, 1}, &nodes_read);
    it->second = b.position(n);
  }
  return it->second;
}

ChunkedMesh::ChunkedMesh(MeshSettings settings) : impl_(std::make_unique<Impl>(settings)) {}
ChunkedMesh::~ChunkedMesh() = default;
ChunkedMesh::ChunkedMesh(ChunkedMesh&&) noexcept = default;
ChunkedMesh& ChunkedMesh::operator=(ChunkedMesh&&) noexcept = default;

const MeshUpdate& ChunkedMesh::update(Field& field, const Camera* camera) {
  Impl& m = *impl_;
  if (camera) camera->validate();
  const bool first = !m.initialised;
  if (first) {
    m.initialise(field);
  } else if (field.ni() != m.dom.ni || field.nj() != m.dom.nj) {
    throw InvalidSetting("mesh.Field.ni",
                         shore::detail::to_text(field.ni()) + " x " + shore::detail::to_text(field.nj()),
                         "must stay " + shore::detail::to_text(m.dom.ni) + " x " + shore::detail::to_text(m.dom.nj) +
                             " (one mesh follows one field)");
  }
  m.field = &field;
  m.camera = camera;
  m.pixels_per_radian = camera ? camera->pixels_per_radian() : 0.0;
  m.nodes_read = 0;
  m.blocks.clear();
  m.node_positions.clear();
  m.dirty_output.clear();
  m.dirty_output_chunks.clear();

  std::vector<GridRect> rects;
  field.take_changes(rects);
  if (first && !m.base)
    rects.assign(1, GridRect{0, 0, static_cast<int>(m.dom.ni), static_cast<int>(m.dom.nj)});  // every node is read once
  std::map<std::uint64_t, GridRect> error_dirty;
  m.apply_changes(rects, error_dirty);

  std::vector<std::uint64_t> dirty;
  Impl::RankQueue seeds(64);
  ++m.pass;
  for (const auto& [index, rect] : error_dirty) {
    m.compute_errors(index, rect, seeds);
    m.summarise(index);
    dirty.push_back(index);
  }
  const std::vector<std::uint64_t> centres = m.saturate_fine(seeds);
  m.update_square_boxes(dirty);
  m.update_coarse(dirty, centres);

  MeshUpdate u;
  m.rebuild_output(u);
  u.triangles = m.triangles;
  u.chunks = m.chunks.size();
  u.nodes_read = m.nodes_read;
  m.last = std::move(u);
  m.field = nullptr;
  m.camera = nullptr;
  m.blocks.clear();
  m.node_positions.clear();
  return m.last;
}

const std::map<ChunkKey, Chunk>& ChunkedMesh::chunks() const noexcept { return impl_->chunks; }
std::size_t ChunkedMesh::triangle_count() const noexcept { return impl_->triangles; }
const MeshSettings& ChunkedMesh::settings() const noexcept { return impl_->s; }

TriangleMesh merge(const ChunkedMesh& mesh, const Field& field) {
  std::map<std::uint64_t, std::uint32_t> index;  // node -> welded vertex
  std::map<std::uint64_t, std::array<float, 3>> normal;
  for (const auto& [key, c] : mesh.chunks())
    for (std::size_t v = 0; v < c.nodes.size(); ++v) {
      index.emplace(c.nodes[v], 0);
      normal.emplace(c.nodes[v], std::array<float, 3>{c.normals[3 * v], c.normals[3 * v + 1], c.normals[3 * v + 2]});
    }
  TriangleMesh out;
  std::uint32_t next = 0;
  const std::uint64_t ni = static_cast<std::uint64_t>(field.ni());
  std::vector<double> p(3);
  for (auto& [node, slot] : index) {
    slot = next++;
    const GridRect r{static_cast<std::int64_t>(node % ni), static_cast<std::int64_t>(node / ni), 1, 1};
    field.positions(r, p);
    out.positions.insert(out.positions.end(), p.begin(), p.end());
    const std::array<float, 3>& n = normal.at(node);
    out.normals.insert(out.normals.end(), n.begin(), n.end());
    out.nodes.push_back(node);
  }
  for (const auto& [key, c] : mesh.chunks())
    for (const std::uint32_t k : c.indices) out.indices.push_back(index.at(c.nodes[k]));
  return out;
}

}  // namespace shore::mesh
