// Measurement helper (not a test): the +-1x and +-2x full-spectrum components of journal
// records against the linear-film and full-film (harmonic balance) forward models for given
// wears, and each model's misfit to each record. Full film three ways: linear AMBs to the 2x,
// the AMB force law to the 2x, the AMB law to the 3x (the wear-id default). Reproduces the
// numbers of docs/journal-bearing.md, "The nonlinear film at e = 0.7" and "The 3x".
//   full_film_probe [--window S] EVENT [EVENT ...] -- D0_UM,GAMMA_DEG,BETA_DEG [...]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/wearid/journal_spectrum.hpp"
#include "host-tools/core/wearid/rig_response.hpp"
#include "host-tools/core/wearid/wear_identification.hpp"
#include "model/journal/wear_geometry.hpp"

using namespace amb;
namespace mj = amb::model::journal;
namespace wi = amb::host::wearid;

namespace {
void print(const char* label, const wi::FullSpectrum& z) {
  std::printf(" %s+ %8.4f%+8.4fj %s- %8.4f%+8.4fj", label, z.forward_m.real() * 1e6, z.forward_m.imag() * 1e6, label,
              z.backward_m.real() * 1e6, z.backward_m.imag() * 1e6);
}
double dist_um(const wi::FullSpectrum& p, const wi::FullSpectrum& q) {
  return 1e6 * std::hypot(std::abs(p.forward_m - q.forward_m), std::abs(p.backward_m - q.backward_m));
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> events;
  std::vector<mj::WearParams> wears;
  std::vector<std::string> names;
  bool after = false;
  double window_s = 2.0;
  for (int a = 1; a < argc; ++a) {
    const std::string s = argv[a];
    if (!after && s == "--window" && a + 1 < argc) {
      window_s = std::atof(argv[++a]);
      continue;
    }
    if (s == "--") {
      after = true;
      continue;
    }
    if (!after) {
      events.push_back(s);
      continue;
    }
    std::stringstream ss(s);
    std::string item;
    std::vector<double> v;
    while (std::getline(ss, item, ',')) v.push_back(std::atof(item.c_str()));
    if (v.size() != 3) {
      std::fprintf(stderr, "wear must be D0_UM,GAMMA_DEG,BETA_DEG (got '%s')\n", s.c_str());
      return 1;
    }
    wears.push_back({mj::WearModel::elliptical, v[0] * 1e-6, v[1] * M_PI / 180.0, v[2] * M_PI / 180.0});
    names.push_back(s);
  }
  if (events.empty() || wears.empty()) {
    std::fprintf(stderr, "usage: full_film_probe [--window S] EVENT [EVENT ...] -- D0_UM,GAMMA_DEG,BETA_DEG [...]\n");
    return 1;
  }
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  for (const auto& e : events) {
    const wi::JournalMeasurement m = wi::measure_journal(host::load_event(e), b, window_s);
    std::printf("%s: eccentricity %.4f, noise per component 1x %.4f um, 2x %.4f um\n  measured     ", e.c_str(), m.eccentricity,
                m.noise_m * 1e6, m.noise_2x_m * 1e6);
    print("1x", m.spectrum);
    print("2x", m.second_harmonic);
    std::printf("\n");
    for (size_t w = 0; w < wears.size(); ++w) {
      const wi::FullSpectrum lin = wi::predict_spectrum(b, wears[w], m.journal, m.speed_hz);
      std::printf("  %-20s linear film", names[w].c_str());
      print("1x", lin);
      std::printf("  misfit 1x %.4f um\n", dist_um(lin, m.spectrum));
      const struct {
        const char* label;
        bool amb;
        int harmonics;
      } variants[] = {{"full, AMBs linear, to 2x", false, 2}, {"full, AMB law, to 2x", true, 2}, {"full, AMB law, to 3x", true, 3}};
      for (const auto& v : variants) {
        wi::HarmonicBalanceOptions o;
        o.max_iterations = 80;
        o.tolerance = 1e-8;
        o.amb_nonlinear = v.amb;
        o.harmonics = v.harmonics;
        const wi::FullFilmSpectrum f = wi::predict_full_film(b, wears[w], m.journal, m.speed_hz, o);
        std::printf("  %-26s", v.label);
        print("1x", f.first);
        print("2x", f.second);
        std::printf("  misfit 1x %.4f um, 2x %.4f um, |Z3| %.4f um (%d iterations%s)\n", dist_um(f.first, m.spectrum),
                    dist_um(f.second, m.second_harmonic),
                    1e6 * std::hypot(std::abs(f.third.forward_m), std::abs(f.third.backward_m)), f.iterations,
                    f.converged ? "" : ", NOT converged");
      }
    }
  }
  return 0;
}
