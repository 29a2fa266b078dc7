#pragma once
// The deformable ground: a grid of vertical soil columns that bodies press into, that
// carries them by Bekker's pressure-sinkage law and whose slopes slump (Sumner, O'Brien &
// Hodgins 1998).
//
// Column (i, j) stands at world (origin_x + i cell, origin_y + j cell) (see
// shore/core/envelope.h). Storage is created on first write, so a large field costs nothing
// until touched; untouched columns read the base height source. Each column keeps its
// height (the collision surface bodies feel) and its sinkage (how far the true envelope
// has pressed it; bearing reads it, so reloading to the same pressure sinks no further;
// negative where loose soil was laid on top, which bears nothing until pressed back down).
//
// Per substep, step() takes every body's lower envelope (an Imprint) and presses, displaces
// and erodes the soil near them; contact() says where and how hard the soil can push on a
// body (shore/terrain/contact.h), bearing() what the soil under an envelope carries,
// bearing_offset() how far it sinks under a load. Results are bit-identical for any thread
// count. docs/terrain.md describes the pipeline stage by stage.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "shore/core/envelope.h"
#include "shore/core/grid_rect.h"
#include "shore/core/vec3.h"
#include "shore/terrain/contact.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/material.h"
#include "shore/terrain/material_image.h"
#include "shore/terrain/spray.h"

namespace shore::terrain {

struct TerrainSettings {
  double cell = 0.01;     ///< m, column spacing, in [1e-4, 1e3]
  double origin_x = 0.0;  ///< m, world x of column (0, 0), in [-1e12, 1e12]
  double origin_y = 0.0;  ///< m, world y of column (0, 0), in [-1e12, 1e12]
  int tile_columns = 64;  ///< columns per tile side, in [4, 1024]
  Material material = Material::sand();
  /// Untouched ground. Null: flat at base_height.
  std::shared_ptr<const HeightSource> base;
  double base_height = 0.0;  ///< m, flat ground level when base is null, finite
  /// Erosion pass cap per step, in [0, 1000]. A rate limit, not a freeze: slopes the cap
  /// leaves too steep keep flowing in the next steps. At 1/240 s and 1 cm, 2 passes bring
  /// a vertical 7 cm sand wall below theta_stop in 0.06 s (8 passes: 0.02 s), still a little
  /// faster than a real slump's time scale, h / sqrt(g h) = 0.085 s.
  int max_erosion_passes = 2;
  int active_margin = 4;  ///< columns added around each imprint window for displacement and erosion, in [1, 256]
  /// m: how far above the soil top a body still counts as over a column. A column whose
  /// (offset) envelope lies higher neither widens the step's active region (a rolling
  /// wheel's footprint is mostly air above its rut) nor holds its slopes at theta_in (a
  /// body 10 cm up supports no soil). Where a pressing imprint reached last step is eroded
  /// once more, so a lifted foot's print relaxes to theta_out. > 0; +infinity: every
  /// covered column counts, however high the body.
  double active_reach = 0.03;
  double contact_tolerance = 1e-4;  ///< m: a column counts as touched when the envelope is within this of its top, >= 0
  int threads = 0;                  ///< threads, 0 = the machine's; results never depend on it, in [0, 1024]
  /// Active regions with fewer columns (halo included) run on one thread: for small
  /// regions forking costs more than it saves, badly so on a loaded machine. Larger ones
  /// fork while the measured parallel steps are faster than serial ones (shore/core/pacer.h).
  /// Results never depend on it. >= 0 (0: always fork onto `threads`, never paced).
  int parallel_min_columns = 16384;
  /// Steps after which a tile no step has worked on is released if it holds nothing but the
  /// untouched base (every height equal to its base, no sinkage, no change not yet taken):
  /// such a tile equals no tile, and is recreated identically when a step reaches it
  /// again, so a body roaming over ground it does not change (or only brushes) leaves no
  /// trail of memory behind. Tiles that differ from the base, or whose heights ever changed
  /// (loaded tiles count as changed), are never released (that would lose soil, or a
  /// change an observer of changed_since() has not seen yet). Results and state_hash() never depend on it. >= 0 (0:
  /// never release).
  int idle_tile_steps = 2400;
  /// Soil thrown into the air by fast bodies (shore/terrain/spray.h): on by default.
  SpraySettings spray;

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;
};

/// One body's imprint for one step.
struct Imprint {
  const EnvelopeRaster* envelope = nullptr;  ///< the body's lower envelope (world heights)
  double offset = 0.0;                       ///< m, >= 0: the envelope is lowered by this much (bearing offset)
  /// Conservative collision surface: lower each column to the lowest (offset) envelope
  /// point within +-1 column, so no heightfield triangle cuts into the body. Sinkage
  /// (soil state) is still taken from the true envelope.
  bool star = false;
  Vec3 velocity{};  ///< m/s, the body's velocity (at its centre of mass), finite
  /// A body at rest: its envelope holds the soil it touches (erosion treats the columns as
  /// under a body, and never fills them above it) but presses nothing, and makes no active
  /// region of its own; it only matters where other bodies or unsettled slopes work. It
  /// sprays nothing: soil clinging to it is set back down.
  bool hold = false;
  /// Columns added around this imprint's reach box, and around what its step carries to
  /// the next (its reach, slopes still flowing), for displacement and erosion, in [0, 256];
  /// 0: the terrain's active_margin. A smaller margin than the terrain's suits a body whose
  /// displaced soil stays near its footprint (a raycast wheel's: docs/terrain.md); a region
  /// where imprints of several margins meet takes the largest.
  int margin = 0;

  // ---- for spray (shore/terrain/spray.h): a point p of the body moves at v + w x (p - c) ----
  Vec3 angular_velocity{};  ///< rad/s, finite
  Vec3 centre{};            ///< m, the point it turns about (its centre of mass), finite
  /// Body to world (|q| within 1e-3 of 1): soil clings to pieces of the body's surface,
  /// found again in the body's frame.
  Quat orientation{};
  /// Names the body from step to step (the soil clinging to it is kept under this key), and
  /// keys its random numbers: give each body the same key every step, whatever the order of
  /// the imprints. Unique among a step's spraying imprints (spray on, not holding).
  std::uint64_t key = 0;
  bool spray = true;  ///< this body throws soil (and the terrain's spray is enabled)
  /// The soil clinging to this body is stepped on every cling_every-th step of the terrain
  /// (those whose spray step count is a multiple of it), in [1, 16], over the time since its
  /// last clinging step (cling_every steps' time while it does not change; after a switch,
  /// what actually passed, so the body sheds what it would stepped every step). For a body
  /// whose surface stays in contact many steps (a rolling wheel's rim), whose pick-up and
  /// shedding then lose nothing the skipped steps would have seen. May change from step to
  /// step. (A body loaded from a state saved before terrain format 9 or soil delta 6 counts
  /// from the step before its load.)
  int cling_every = 1;
};

/// Force one contact column can carry at its sinkage.
struct ColumnForce {
  std::int64_t i = 0, j = 0;
  double force = 0.0;  ///< N
};

/// What the soil under an envelope can bear.
struct Bearing {
  /// N: sum over contact columns of p_yield(z) cell^2 with z each column's sinkage if
  /// pressed to the (offset) envelope; +infinity if any contact column is at bedrock or
  /// the material is rigid.
  double capacity = 0.0;
  double patch_width = 0.0;  ///< m, b: the smaller width of the contact patch
  int contact_columns = 0;
  std::vector<ColumnForce> columns;  ///< per-column share of capacity (same order as the window)
};

struct StepReport {
  int active_columns = 0;       ///< columns visited by the pipeline this step
  int contact_columns = 0;      ///< columns pushed down by a body
  int erosion_passes = 0;       ///< passes until every slope was below theta_stop (or the cap)
  double displaced_volume = 0;  ///< m^3 pushed down by collision this step
  double compacted_volume = 0;  ///< m^3 of it kept as compaction
  // spray, this step
  int particles_created = 0;  ///< particles thrown
  int particles_landed = 0;   ///< particles that landed on a column
  int particles_lost = 0;     ///< particles that left the region or the world
  double picked_volume = 0;   ///< m^3 of soil the bodies picked up
};

/// Volume bookkeeping, m^3, relative to the untouched base: ground + compacted + airborne
/// + lost stays equal to its start value (zero, plus what set_height added) to rounding.
struct VolumeTotals {
  double ground = 0.0;     ///< sum of (height - base height) cell^2 over touched columns
  double compacted = 0.0;  ///< volume removed from the surface by compression
  /// Spray: soil off the ground, in flight as particles or clinging to bodies (the latter
  /// also in `clinging`).
  double airborne = 0.0;
  double clinging = 0.0;  ///< the part of airborne clinging to bodies, not yet shed
  /// Spray that left the terrain's region or the world (SpraySettings): gone, and counted
  /// here, apart from the rest.
  double lost = 0.0;
  /// Net volume added by set_height (an outside edit): ground + compacted + airborne + lost
  /// equals this to rounding. Not part of total().
  double edited = 0.0;
  [[nodiscard]] double total() const { return ground + compacted + airborne + lost; }
};

class Terrain {
 public:
  explicit Terrain(TerrainSettings settings);
  ~Terrain();
  Terrain(Terrain&&) noexcept;
  Terrain& operator=(Terrain&&) noexcept;

  [[nodiscard]] const TerrainSettings& settings() const noexcept;
  /// Changes the material (palette entry 0, the columns never painted) from the next step
  /// on (a viewer's live tweak of alpha, Bekker's or the erosion parameters). Throws
  /// InvalidSetting if it is invalid, or if its
  /// soil_depth or rigid flag differ from the present material's (they define bedrock and
  /// the tiles' kind).
  void set_material(const Material& material);

  // ---- material map ----
  // Every column has a material: an index into the palette, one byte per column in the
  // tiles. A new terrain has a one-entry palette (settings().material) and every column at
  // index 0; a terrain that never paints computes and costs exactly what a one-material
  // terrain did. Each column's soil follows its own material: bearing and contact (Bekker,
  // remoulding, unloading, walls), displacement and compaction (alpha), erosion (a column
  // gives by its own slope limits and sigma, so sand slumping onto gravel keeps sand's
  // angle). The map belongs to the columns, like a painted texture: soil that displacement
  // or erosion moves onto a column becomes that column's material, so volume is conserved
  // in total, not per material. Shore's Bullet coupling shears each column by its own
  // material too. A rigid entry on deforming ground (a road, a rock) has its bedrock at its
  // columns' untouched top: they carry any load and are never pressed, carried off or
  // eroded below it (loose soil laid on them can move again). Spray: a body picks up the
  // adhesion of the column it touches; what it sheds and throws (particle size, half-life,
  // drag, speeds) is entry 0's.

  /// At most this many materials.
  static constexpr int kMaxMaterials = 256;
  /// The palette; entry 0 is settings().material.
  [[nodiscard]] std::span<const Material> palette() const noexcept;
  /// Replaces the palette (entry 0 becomes settings().material), from the next step on.
  /// Throws InvalidSetting (terrain untouched) if it is empty or longer than kMaxMaterials,
  /// an entry is invalid, an entry's soil_depth differs from the present material's (it
  /// defines bedrock), entry 0's rigid flag differs from the present material's, an entry
  /// of a rigid terrain is not rigid (rigid ground never steps), or it is shorter than an
  /// index painted on the map. Entries after 0 may be rigid on deforming ground.
  void set_palette(std::vector<Material> palette);
  /// The column's palette index (0 where never painted).
  [[nodiscard]] int material_index(std::int64_t i, std::int64_t j) const;
  /// The column's material.
  [[nodiscard]] const Material& material_at(std::int64_t i, std::int64_t j) const;
  /// Palette indices of a rectangle of columns, row-major (out.size() == nx * ny), one tile
  /// lookup per run of columns. Throws InvalidSetting on a size mismatch.
  void material_indices(const GridRect& rect, std::span<std::uint8_t> out) const;
  /// Whole tiles (in key order) whose palette indices were written after generation g
  /// (Terrain::generation): what a renderer's or a replica's copy of the map must read
  /// again. painted_since(0) is empty for a terrain that never painted.
  [[nodiscard]] std::vector<GridRect> painted_since(std::uint64_t g) const;
  /// Paints every column of the rectangle with palette entry `index`. Throws InvalidSetting
  /// naming the value and the allowed range [0, palette size) (terrain untouched) if the
  /// index is not in the palette, or the rectangle is negative.
  void paint_rect(const GridRect& rect, int index);
  /// Paints the columns whose centres lie within `radius` (m, >= 0, finite) of world
  /// (x, y) (finite). Throws like paint_rect, and for a bad centre or radius.
  void paint_disc(double x, double y, double radius, int index);
  /// Paints the columns of the rectangle whose centre (x, y) satisfies inside(x, y).
  /// Throws like paint_rect.
  void paint_where(const GridRect& rect, const std::function<bool(double x, double y)>& inside, int index);
  /// Paints an image of indices (shore/terrain/material_image.h) onto `rect`, which must be
  /// the image's size (pixel (c, r) is column (rect.i0 + c, rect.j0 + rows - 1 - r)).
  /// Throws InvalidSetting (terrain untouched) on a size mismatch, naming both sizes and
  /// the image, or a pixel whose index is beyond the palette, naming the image, the pixel,
  /// its value and the allowed range.
  void paint_image(const MaterialImage& image, const GridRect& rect);

  // ---- layers in depth ----
  // A column may hold a second, lower material under its own (a crust over soft soil, snow
  // over ice): its painted index is the crust, and the crust ends `depth` below the column's
  // top as painted (at sinkage max(0, sinkage) + depth, m). Its Bekker law has two pieces,
  // continuous in pressure: the crust's p_u(z) while the sinkage z stays within the crust,
  // then p_u(d) + p_l(z - d) beyond it (the lower soil's own law, from fresh, on top of the
  // pressure the crust reached). Bearing, contact (yield pressure, pressure rate,
  // unloading) read it. A column pressed beyond its crust is broken through: from then on
  // it reads as its lower material wherever the column's material decides (alpha while
  // pressed beyond the crust, erosion's slope limits, shear and remoulding, unloading):
  // exposed_index. Painting a column's index (paint_rect...) keeps its layer; clear_layers
  // removes it. A terrain that never paints a layer computes and costs as before.

  /// Gives every column of the rectangle a lower layer of palette entry `lower_index`
  /// under a crust `depth` m thick (finite, in [0, 1e6]). Throws InvalidSetting naming the
  /// field, the value and the allowed range (terrain untouched) for an index beyond the
  /// palette, a bad depth or a negative rectangle.
  void paint_layer_rect(const GridRect& rect, int lower_index, double depth);
  /// The same on the columns whose centres lie within `radius` of (x, y) (as paint_disc).
  void paint_layer_disc(double x, double y, double radius, int lower_index, double depth);
  /// The same on the columns of the rectangle whose centre satisfies inside(x, y).
  void paint_layer_where(const GridRect& rect, const std::function<bool(double x, double y)>& inside, int lower_index,
                         double depth);
  /// Removes the layers of the rectangle's columns (their painted index stays).
  void clear_layers(const GridRect& rect);
  /// The column's lower palette index, or -1 where it is not layered.
  [[nodiscard]] int lower_index(std::int64_t i, std::int64_t j) const;
  /// The sinkage at which the column's crust ends, m (+infinity where not layered).
  [[nodiscard]] double layer_boundary(std::int64_t i, std::int64_t j) const;
  /// The palette index the column shows: its lower layer's once its sinkage is beyond its
  /// crust (broken through), else material_index.
  [[nodiscard]] int exposed_index(std::int64_t i, std::int64_t j) const;
  /// The material of exposed_index.
  [[nodiscard]] const Material& exposed_material(std::int64_t i, std::int64_t j) const;

  // ---- grid geometry ----
  [[nodiscard]] std::int64_t column_i(double x) const;  ///< nearest column to world x
  [[nodiscard]] std::int64_t column_j(double y) const;  ///< nearest column to world y
  [[nodiscard]] double column_x(std::int64_t i) const;
  [[nodiscard]] double column_y(std::int64_t j) const;

  // ---- state of one column ----
  [[nodiscard]] double height(std::int64_t i, std::int64_t j) const;  ///< collision surface, m
  /// Plastic sinkage, m: how far the column's firm soil has been pressed below its
  /// uncompacted level; negative by the height of loose soil that displacement or erosion
  /// laid on it (loose soil bears nothing until pressed back to the firm level).
  [[nodiscard]] double sinkage(std::int64_t i, std::int64_t j) const;
  /// Heights of a rectangle of columns, row-major (out.size() == nx * ny): the bulk form of
  /// height(), one tile lookup per run of columns. Throws InvalidSetting on a size mismatch.
  void heights(const GridRect& rect, std::span<double> out) const;
  /// Untouched ground heights of a rectangle, like heights() (bedrock = base - soil depth).
  void base_heights(const GridRect& rect, std::span<double> out) const;
  [[nodiscard]] double base_height(std::int64_t i, std::int64_t j) const;  ///< untouched ground, m
  /// base height - soil depth, m (base height on a rigid palette entry's column)
  [[nodiscard]] double bedrock(std::int64_t i, std::int64_t j) const;
  /// Writes a height directly (editing tools, tests); keeps volume accounting in step: the
  /// change is added to VolumeTotals::edited and reported by take_changed. Heights below
  /// bedrock are raised to bedrock; sinkage is left as it is. Throws InvalidSetting if h is
  /// not finite.
  void set_height(std::int64_t i, std::int64_t j, double h);

  // ---- physics ----
  /// What the soil under the envelope, lowered by offset, can carry (Bekker). A column
  /// touches when the lowered envelope lies within contact_tolerance of its top; its z is
  /// its sinkage plus how far the lowered envelope lies below its top; b is the smaller
  /// side of the touching columns' bounding box, each column one cell wide. Reads only
  /// (never creates tiles). Throws InvalidSetting on a bad envelope or offset.
  [[nodiscard]] Bearing bearing(const EnvelopeRaster& envelope, double offset = 0.0) const;
  /// The downward offset (m, >= 0) of the envelope at which the bearing capacity equals
  /// load (N); 0 if the soil already carries it, and 0 if the envelope covers no column.
  /// Bracketed regula falsi / bisection to 1e-7 m; returns the upper end of the bracket, so
  /// bearing(envelope, result).capacity >= load. Columns pressed to bedrock carry anything,
  /// so the result never exceeds the depth to bedrock.
  [[nodiscard]] double bearing_offset(const EnvelopeRaster& envelope, double load) const;
  /// The soil's side of a body's contact (shore/terrain/contact.h) into `out`.
  /// shear: the length (m) of the shear displacement the body has put into the soil at each
  /// raster column while in contact (it remoulds the soil: shear::remoulding), in the
  /// raster's layout, or empty (all 0). probe: the body's underside at any point, for
  /// sub-cell coverage at the footprint's edges; null: whole columns. Reads only. Throws
  /// InvalidSetting on a bad envelope or a shear of the wrong size.
  void contact(const EnvelopeRaster& envelope, std::span<const double> shear, const SurfaceProbe* probe,
               ContactPatch& out) const;
  /// One step of the pipeline for all imprints together: collision, contour map,
  /// displacement, erosion, over the active region only. Throws InvalidSetting (grid
  /// untouched) if an envelope holds NaN or -inf, its size does not match nx * ny, an
  /// offset is negative or not finite, or a velocity is not finite. Rigid material: no-op.
  StepReport step(std::span<const Imprint> imprints);
  /// The same step lasting dt seconds (>= 0, finite): spray particles fly for dt, bodies
  /// pick soil up and shed it (shore/terrain/spray.h). dt = 0 is step(imprints): no time
  /// passes, so nothing sprays and particles hold still. Also throws InvalidSetting for a
  /// bad dt, a non-finite angular velocity or centre, a quaternion that is not a unit, or
  /// (with dt > 0) two spraying imprints with the same body key.
  StepReport step(std::span<const Imprint> imprints, double dt);
  /// Erosion alone over a region (e.g. to relax a pile that was set by set_height), run to
  /// rest: passes repeat while material moves (theta_stop is ignored), at most
  /// max_erosion_passes; call again while erosion_passes == max_erosion_passes. No column
  /// is in contact; the one-column ring around the region receives but does not give.
  StepReport relax(const GridRect& region);

  // ---- output ----
  /// Rectangles of columns whose height changed since the last call (for push-back): at
  /// most one per tile, the bounding box of that tile's changed columns, in tile key order.
  /// After load() every loaded tile is reported whole.
  std::vector<GridRect> take_changed();
  /// The change generation: it advances with every call that may change heights (step,
  /// relax, set_height) or the material map (set_palette, paint_*), and every height
  /// change is stamped with it (and the palette and each repainted tile, for soil deltas). An observer (a mesh,
  /// a network delta) remembers generation() when it reads the heights and later asks
  /// changed_since(that) what changed since; any number of observers can do so, and
  /// take_changed is unaffected. Starts at 1 (load() too: loaded tiles are generation 1).
  [[nodiscard]] std::uint64_t generation() const noexcept;
  /// Rectangles covering every column whose height changed after generation g, at most one
  /// per tile, in tile key order: the bounding box of that tile's changes after g, or the
  /// whole tile when g is older than the recent history kept (a few changes per tile).
  /// changed_since(0): every column ever changed. Reads only.
  [[nodiscard]] std::vector<GridRect> changed_since(std::uint64_t g) const;
  [[nodiscard]] VolumeTotals volume() const;
  /// The spray particles in flight, in their fixed order (positions, radii, volumes).
  [[nodiscard]] std::vector<SprayParticle> spray_particles() const;
  [[nodiscard]] SprayCounts spray_counts() const;
  /// s of wall time spent in spray since creation (for benchmarks; not part of the state).
  [[nodiscard]] double spray_seconds() const;
  /// FNV-1a over the bookkeeping, the tiles in key order (leaving out tiles that hold
  /// nothing but the untouched base: they equal no tile, so the same soil gives the same
  /// hash whichever idle tiles were released, TerrainSettings::idle_tile_steps) and the
  /// spray (particles and clinging soil, in their fixed orders). The material map counts
  /// only on tiles where it is painted (not all index 0), so a terrain that never paints
  /// keeps the hashes of a one-material terrain; the palette's values are settings, not state.
  [[nodiscard]] std::uint64_t state_hash() const;
  [[nodiscard]] std::size_t tile_count() const;  ///< tiles held now (created on first write, released when idle)
  [[nodiscard]] std::size_t memory_bytes() const;

  /// Bit-exact round trip of the touched state. The file holds the settings (but not the
  /// base source: pass the same one to load, or null for flat ground at the saved
  /// base_height), the bookkeeping (compacted, edited, lost), the regions still eroding,
  /// every tile's heights, sinkage and sampled base, and the spray (particles, clinging
  /// soil, counts); a checksum guards the whole file (terrain/src/terrain_io.cpp describes
  /// the format). Files written before spray existed (version 3 and older) load with spray
  /// switched off, the behaviour they were stepped with.
  ///
  /// save() writes `<file>.tmp`, flushes it to the disk and renames it over `file`, so the
  /// old file stays whole and loadable whatever happens during the write: a full disk, a
  /// folder that refuses the write, the process killed mid-write (a `<file>.tmp` may then be
  /// left behind; the next save overwrites it). It throws shore::FileError naming the file,
  /// the step that failed and the system's cause ("No space left on device").
  void save(const std::filesystem::path& file) const;
  /// Throws shore::FileError naming the file and the problem: unreadable, truncated,
  /// corrupt (checksum), not a terrain state, or another format version, byte order or
  /// precision than this build reads (each refused with a message saying so). Never
  /// crashes, whatever the bytes (the loaders are fuzzed: fuzz/README.md).
  static Terrain load(const std::filesystem::path& file, std::shared_ptr<const HeightSource> base = nullptr);
  /// The same state as save() writes, as bytes (a checkpoint embeds them whole, so whatever
  /// the terrain adds to its own format comes with it), and its inverse; `name` says where
  /// the bytes came from in load_bytes' FileError messages.
  [[nodiscard]] std::vector<unsigned char> save_bytes() const;
  /// load() from bytes already in memory (a checkpoint, an archive, a network buffer).
  static Terrain load_bytes(std::span<const unsigned char> bytes, const std::string& name,
                            std::shared_ptr<const HeightSource> base = nullptr);

 private:
  friend class SoilDelta;     // reads and writes columns in bulk (shore/terrain/soil_delta.h)
  friend class BearingSolve;  // reads the columns under an envelope once for several loads
  void read_rect(const GridRect& rect, std::span<double> out, bool base) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace shore::terrain
