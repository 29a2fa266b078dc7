#pragma once
// Pictures of height grids: shaded relief (top view) coloured by deformation or height, an
// oblique 3-D view, a water-surface view, filmstrips of several frames, and the scenes'
// relief and oblique frames with bodies drawn.

#include <string>
#include <vector>

#include "shore/scenes/envelopes.h"
#include "shore/scenes/height_grid.h"
#include "shore/scenes/image.h"

namespace shore::scenes {

/// A colour bar under a picture: one of the colour maps (image.h) with its low, middle
/// and high labels.
struct Legend {
  enum class Map { diverging, height, water };
  Map map = Map::diverging;
  std::string low, mid, high;
};

/// "-3.2 mm", "+12 um", "0.150 m": how the pictures label lengths (signed: a + on positive values).
std::string format_length(double metres, bool signed_value);

/// The labels of the deformation colour bar for a scale of `scale` metres: "-x lowered", "0", "raised +x".
Legend deformation_legend(double scale);

/// The picture with a title strip above (none if empty) and the legend's colour bar below
/// (none if null), on white, at least 480 pixels wide with a legend.
Image framed_picture(const Image& picture, const std::string& title, const Legend* legend);

/// Lambertian hillshade in [0, 1] of each column: light from azimuth (degrees clockwise
/// from +y, "north") and altitude (degrees above the horizon); heights multiplied by
/// exaggeration. Central differences inside, one-sided at the edges.
std::vector<double> hillshade(const HeightGrid& grid, double azimuth_deg = 315.0, double altitude_deg = 45.0,
                              double exaggeration = 1.0);

/// A small sphere drawn over a picture (a spray particle), world coordinates, m.
struct Dot {
  double x = 0.0, y = 0.0, z = 0.0, radius = 0.0;
};

struct ReliefStyle {
  /// If set (same size as the heights), colour by heights - baseline with the diverging
  /// map (blue lowered, red raised, neutral untouched); otherwise colour by height.
  const HeightGrid* baseline = nullptr;
  double deformation_scale = 0.0;  ///< m mapped to full colour; 0: the largest |change|
  /// Optional upper envelope of bodies (NaN where none, same grid as the heights): drawn
  /// solid in the oblique view, tinted with an outline in the top view.
  const HeightGrid* bodies = nullptr;
  /// Optional lower envelope of the same bodies; without it bodies reach down to the ground.
  const HeightGrid* body_bottoms = nullptr;
  double exaggeration = 1.0;  ///< vertical exaggeration of the shading and of the oblique view
  int min_pixels = 480;       ///< the longer image side is at least this (grids are upsampled)
  std::string title;          ///< printed above the picture (empty: none)
  bool legend = true;         ///< colour bar with its range under the picture
  /// Optional spray particles, drawn over the ground as dark dots (at least 1.5 pixels
  /// across, so a few millimetres show on a metre-wide picture).
  const std::vector<Dot>* spray = nullptr;
};

/// Top view: shaded relief coloured by deformation (or height), north up.
Image render_relief(const HeightGrid& heights, const ReliefStyle& style = {});

/// Oblique orthographic view from the south, looking down at elevation_deg.
Image render_oblique(const HeightGrid& heights, const ReliefStyle& style = {}, double elevation_deg = 35.0);

/// Top view of a water surface: colour by height relative to rest_level (scale: metres
/// to full colour; 0 = the largest |deviation|), with shading.
Image render_water(const HeightGrid& surface, double rest_level, double scale = 0.0, const std::string& title = {},
                   int min_pixels = 480);

/// Frames side by side in rows of `columns`, each with its label underneath.
Image filmstrip(const std::vector<Image>& frames, const std::vector<std::string>& labels, int columns = 3);

/// The top view of one moment: relief coloured by deformation from `baseline` (by height
/// without one), bodies tinted and outlined (if given), with a legend.
Image relief_frame(const HeightGrid& heights, const HeightGrid* baseline, const BodyEnvelopes* bodies, int min_pixels,
                   const std::string& title, const std::vector<Dot>* spray = nullptr);

/// The oblique picture of one moment: relief coloured by deformation, bodies and spray
/// particles (if given) drawn.
Image oblique_frame(const HeightGrid& heights, const HeightGrid& baseline, const BodyEnvelopes* bodies,
                    double exaggeration, int min_pixels, const std::string& title, double deformation_scale = 0.0,
                    double elevation_deg = 35.0, bool legend = false, const std::vector<Dot>* spray = nullptr);

}  // namespace shore::scenes
