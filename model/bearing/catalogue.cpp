#include "model/bearing/catalogue.hpp"

#include <array>
#include <cctype>

namespace amb::model::bearing {
namespace {

constexpr double k_inch_m = 0.0254;

// Sources:
// - 6205: CWRU drive-end bearing (data/measured/README.md): 9 balls, 0.3126 in, pitch 1.537 in.
// - 6206: seed 003 section 3: 9 balls, D 9.525 mm, D_m 46 mm.
// - 6200: seed 001 Table 5: 8 balls, 4.76 mm; D_m = (10 + 30)/2 mm from its "race diameters"
//   (those are really bore and OD of a 6200). The 49.3 deg contact angle of Table 5 is not
//   used: the seed's own 762 rpm / 101.6 Hz figures require alpha = 0.
// - 6203: CWRU fan-end bearing (data/measured/README.md): 8 balls, 0.2656 in, pitch 1.122 in;
//   its published orders BPFI 4.9469, BPFO 3.0530, FTF 0.3817, BSF 1.9937 are reproduced.
constexpr std::array<BearingGeometry, 4> k_catalogue{{
    {"SKF 6205", 9, 0.3126 * k_inch_m, 1.537 * k_inch_m, 0.0,
     "CWRU drive-end bearing, data/measured/README.md"},
    {"SKF 6206", 9, 9.525e-3, 46.0e-3, 0.0, "seed 003 section 3"},
    {"SKF 6200", 8, 4.76e-3, 20.0e-3, 0.0,
     "seed 001 Table 5 (pitch diameter = mean of its 10/30 mm race diameters; alpha=0)"},
    {"SKF 6203", 8, 0.2656 * k_inch_m, 1.122 * k_inch_m, 0.0,
     "CWRU fan-end bearing, data/measured/README.md"},
}};

// Reduce a name to its significant characters: drop "skf", spaces, and anything after '-'.
std::array<char, 32> normalise(std::string_view s) {
  std::array<char, 32> out{};
  size_t n = 0;
  for (char c : s) {
    if (c == '-') break;
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    if (n + 1 < out.size()) out[n++] = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  std::string_view v(out.data(), n);
  if (v.starts_with("skf")) {
    std::array<char, 32> rest{};
    for (size_t i = 3; i < n; ++i) rest[i - 3] = out[i];
    return rest;
  }
  return out;
}

}  // namespace

std::span<const BearingGeometry> bearing_catalogue() { return k_catalogue; }

std::optional<BearingGeometry> find_bearing(std::string_view name) {
  const auto key = normalise(name);
  for (const auto& g : k_catalogue) {
    if (normalise(g.name) == key) return g;
  }
  return std::nullopt;
}

}  // namespace amb::model::bearing
