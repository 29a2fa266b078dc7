#pragma once
// Internal: what a body's terrain contact remembers per column of the body's envelope from
// one substep to the next (docs/terrain.md, "Soil contact" and "Unloading"):
// - shear displacement: the slip of the body along the surface over the column, summed as
//   a vector while the column is touched (Janosi-Hanamoto's j is its length, which also
//   remoulds the soil); slip that reverses undoes itself. Columns out of contact restart
//   from zero.
// - remould displacement: the length of the shear displacement when the column last
//   yielded (the body pressed further into it while its block pushed with its whole
//   capacity, or its elastic push reached its yield pressure). A column pressed while its
//   block held below its capacity carried part of its yield pressure, and one the body
//   slides along without approaching it (or approaching it by less than a twentieth of its
//   slip: a gliding box's rocking) is not compressed further: neither flows.
//   The strength loss (Material::remould_shear_ratio) follows it: soil remoulds where it
//   flows, and soil that carries a sliding body elastically shears as a bevameter's shear
//   ring measures it, whose plateau c and phi already are (docs/terrain.md, "Validation
//   matrix"). Rigid-plastic soil yields wherever it is touched: there it is the shear
//   displacement's length.
// - unloading pressure: what a column that unloads elastically pushed with at the end of the
//   last substep (Pa). Wong's unloading starts from the pressure a column carried: soil
//   that erosion lays under a body raises the column's top, and with it the elastic line,
//   without loading it; remembering the pressure keeps that soil from pushing until the body
//   presses it. A column pressed while its block held below capacity remembers the share
//   of its yield pressure it carried: a fast impact overlaps the soil by a substep's travel
//   before its contact is seen, and the imprint then sinks the columns that far, to a yield
//   pressure (and an elastic push) the body never paid for. Columns whose block yielded, or
//   out of contact, remember nothing (+infinity).

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "contact_solver.h"
#include "shore/bullet/config.h"
#include "shore/core/byte_io.h"
#include "shore/core/envelope.h"
#include "shore/core/vec3.h"
#include "shore/terrain/contact.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace contact_detail {

class ContactMemory {
 public:
  /// No unloading pressure remembered.
  static constexpr double kNone = std::numeric_limits<double>::infinity();

  /// m per envelope column: the length of each shear displacement (empty: none yet).
  [[nodiscard]] std::span<const double> shear_length() const noexcept { return shear_length_; }
  /// m per envelope column: the remould displacement (empty: none yet).
  [[nodiscard]] std::span<const double> remould_length() const noexcept { return remould_; }

  /// Moves the values from the envelope window `from` to `to` (columns that leave it are
  /// forgotten, new ones start fresh).
  void remap(const GridRect& from, const GridRect& to);
  /// An unloading element pushes at most with what its column carried at the end of the
  /// last substep.
  void limit_unloading(std::span<terrain::ContactElement> elements, const EnvelopeRaster& envelope) const;
  /// The substep's end: each touched column's shear displacement grows by the body's slip
  /// over it (a fringe element moves its covered column's), its remould displacement becomes
  /// the new length where the element yields and stays at most that elsewhere (a column
  /// touched for the first time starts from 0 unless it yields), and an unloading column keeps
  /// its spring's push at the body's final approach speed over it, within [0, its yield
  /// pressure], which is also written into its element's preload (a contact that follows
  /// the body starts from it). A column being pressed whose block (of `blocks`, solved,
  /// gathered with `block_columns`) held below its capacity carried that share of its yield
  /// pressure, and unloads from it; one whose block yielded carried its yield pressure
  /// (nothing remembered). Not for articulated bodies: a link's solve is not the load of
  /// its columns, which the links solved after it add to through their joints.
  void advance(std::span<terrain::ContactElement> elements, const EnvelopeRaster& envelope, const SolverBody& body,
               std::span<const Block> blocks, int block_columns, double h);

  /// Field by field: shear displacements, their lengths, unloading pressures, remould
  /// displacements.
  void save(ByteWriter& w) const;
  /// Reads save's form for an envelope of `columns` columns; FileError for sizes that do not
  /// fit it, non-finite displacements or negative pressures. with_remould false: a state
  /// saved before the remould displacement was kept (it is taken as the shear's length,
  /// the strength loss those states had).
  void restore(ByteReader& r, std::size_t columns, bool with_remould);

 private:
  std::vector<Vec3> shear_;
  std::vector<double> shear_length_;
  std::vector<double> unloading_;
  std::vector<double> remould_;
  // The raster indices whose values may differ from fresh (the columns touched last
  // substep, remapped with the window): a substep resets just these instead of refilling
  // arrays the window's size (a wheel's window is three times its patch).
  std::vector<std::uint32_t> touched_;
  // Scratch of advance: the new values by raster index, in element order.
  struct NewShear {
    std::uint32_t k;  // raster index
    Vec3 j;
    double length, remould;  // m: |j| and the remould displacement
  };
  std::vector<NewShear> new_shear_;
  std::vector<std::pair<std::uint32_t, double>> new_unloading_;
};

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
