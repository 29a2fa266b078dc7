#pragma once
// The scenes' pictures: what a scene asks a picture to show (a View: where the camera is,
// how ground and water are coloured, the title and the colour bar), drawn by a Painter.
// shore::render's OpenGL renderer is the painter (shore/render/painter.h, headless through
// EGL); the scenes know nothing of OpenGL. Without a painter a run writes no pictures and
// says so (Drawing::skipped, metrics "pictures_skipped").
//
// The frame around a picture is drawn here: a title strip above and the colour bar users
// read millimetres from below (framed_picture), and filmstrips of several frames.

#include <string>
#include <vector>

#include "shore/scenes/contents.h"
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

/// Frames side by side in rows of `columns`, each with its label underneath. Throws
/// InvalidSetting for no frames.
Image filmstrip(const std::vector<Image>& frames, const std::vector<std::string>& labels, int columns = 3);

/// What one picture shows.
struct View {
  enum class Camera {
    oblique,  ///< from `azimuth_deg`, `elevation_deg` above the horizon, framing the region
    top,      ///< straight down, north (+y) up, framing the region (a narrow lens: nearly orthographic)
  };
  enum class Ground { natural, deformation, sinkage, height };
  enum class Water { automatic, natural, height, velocity };  ///< automatic: height without soil, else natural
  Camera camera = Camera::oblique;
  Bounds region = {};           ///< the world rectangle framed; empty: the scene's bounds
  double target_z = 0.0;        ///< m, the height the region is framed at
  double elevation_deg = 35.0;  ///< oblique: the eye's elevation above the horizon, in [5, 85]
  double azimuth_deg = -90.0;   ///< oblique: where the eye is, degrees from +x counter-clockwise (-90: the south)
  Ground ground = Ground::deformation;
  Water water = Water::automatic;
  double colour_scale = 0.0;  ///< m (m/s for velocity) to full colour; 0: the largest in the picture
  bool legend = true;         ///< the colour bar under the picture
  bool mesh_edges = false;    ///< outline the soil and water meshes' triangles (their level of detail)
  bool spray = true;          ///< the soils' spray particles in flight, as dark crosses
  bool bodies = true;         ///< the world's bodies (false: the ground alone)
  int width = 1280;           ///< pixels of the 3-D view, >= 16
  int height = 0;             ///< pixels; 0: the region's aspect for a top view, 9 / 16 of the width otherwise
  std::string title = {};     ///< above the picture (empty: none)
};

/// Draws pictures of a scene's contents.
class Painter {
 public:
  virtual ~Painter() = default;
  /// The picture of the contents as they are now, framed (title, colour bar). Throws
  /// InvalidSetting for a bad view, std::invalid_argument for contents with nothing to draw.
  virtual Image paint(const SceneContents& contents, const View& view) = 0;
};

}  // namespace shore::scenes
