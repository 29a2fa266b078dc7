// Palette files (shore/terrain/material_palette.h).

#include "shore/terrain/material_palette.h"

#include <cerrno>
#include <cstdlib>
#include <sstream>
#include <utility>

#include "shore/core/error.h"
#include "shore/core/file_bytes.h"

namespace shore::terrain {

namespace {

constexpr std::size_t kMaxEntries = 256;

/// The Material field a key names, or null.
double* number_field(Material& m, const std::string& key) {
  const std::pair<const char*, double*> fields[] = {
      {"theta_stop", &m.theta_stop},
      {"sigma", &m.sigma},
      {"theta_in", &m.theta_in},
      {"theta_out", &m.theta_out},
      {"alpha", &m.alpha},
      {"bekker_n", &m.bekker_n},
      {"bekker_kc", &m.bekker_kc},
      {"bekker_kphi", &m.bekker_kphi},
      {"cohesion", &m.cohesion},
      {"friction_angle", &m.friction_angle},
      {"shear_modulus", &m.shear_modulus},
      {"remould_ratio", &m.remould_ratio},
      {"remould_shear_ratio", &m.remould_shear_ratio},
      {"remould_length", &m.remould_length},
      {"unload_modulus", &m.unload_modulus},
      {"friction", &m.friction},
      {"soil_depth", &m.soil_depth},
      {"spray.adhesion", &m.spray.adhesion},
      {"spray.half_life", &m.spray.half_life},
      {"spray.speed_scale", &m.spray.speed_scale},
      {"spray.exponent", &m.spray.exponent},
      {"spray.particle_size", &m.spray.particle_size},
      {"spray.min_speed", &m.spray.min_speed},
      {"spray.jitter", &m.spray.jitter},
      {"spray.drag", &m.spray.drag},
  };
  for (const auto& [name, field] : fields)
    if (key == name) return field;
  return nullptr;
}

/// The whole text as a number (strtod's syntax), or false.
bool to_number(const std::string& text, double& out) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return errno == 0 && end == text.c_str() + text.size();
}

class LineReader {
 public:
  LineReader(std::string name, int line) : where_("palette " + std::move(name) + ", line " + std::to_string(line)) {}
  [[noreturn]] void fail(const std::string& problem) const { throw FileError(where_ + ": " + problem); }

  /// One line's material: the preset, then each field=value in order.
  Material material(std::istringstream& words) const {
    std::string preset;
    if (!(words >> preset)) fail("index without a preset (one of sand, mud, snow, rigid)");
    Material m;
    try {
      m = Material::preset(preset);
    } catch (const InvalidSetting&) {
      fail("unknown preset \"" + preset + "\" (one of sand, mud, snow, rigid)");
    }
    for (std::string word; words >> word;) set(m, word);
    try {
      m.validate();
    } catch (const InvalidSetting& e) {
      fail(e.what());
    }
    return m;
  }

 private:
  void set(Material& m, const std::string& word) const {
    const std::size_t eq = word.find('=');
    if (eq == std::string::npos || eq == 0) fail("\"" + word + "\" is not field=value");
    const std::string key = word.substr(0, eq), value = word.substr(eq + 1);
    if (key == "name") {
      if (value.empty()) fail("empty name");
      m.name = value;
      return;
    }
    double number = 0.0;
    if (!to_number(value, number)) fail(key + " = \"" + value + "\" is not a number");
    if (key == "rigid") {
      if (number != 0.0 && number != 1.0) fail("rigid = " + value + " must be 0 or 1");
      m.rigid = number == 1.0;
      return;
    }
    double* field = number_field(m, key);
    if (field == nullptr) fail("unknown field \"" + key + "\"");
    *field = number;
  }

  std::string where_;
};

}  // namespace

std::vector<Material> parse_palette(std::string_view text, const std::string& name) {
  std::vector<Material> palette;
  std::istringstream lines{std::string(text)};
  int line_number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::string index_word;
    if (!(words >> index_word)) continue;  // blank or comment
    const LineReader reader(name, line_number);
    double index = 0.0;
    if (!to_number(index_word, index) || index != static_cast<double>(palette.size()))
      reader.fail("index \"" + index_word + "\" where " + std::to_string(palette.size()) +
                  " was expected (indices run from 0 without gaps, in order)");
    if (palette.size() == kMaxEntries) reader.fail("more than " + std::to_string(kMaxEntries) + " materials");
    palette.push_back(reader.material(words));
  }
  if (palette.empty()) throw FileError("palette " + name + ": no materials");
  return palette;
}

std::vector<Material> read_palette(const std::filesystem::path& file) {
  const std::vector<unsigned char> bytes = read_file_bytes(file, "palette");
  return parse_palette(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), file.string());
}

}  // namespace shore::terrain
