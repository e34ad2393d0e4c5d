#include "host-tools/core/report/frf_overlay.hpp"

#include <cmath>
#include <limits>

#include "host-tools/core/report/svg_plot.hpp"

namespace amb::host::report {

std::string render_frf_overlay_svg(const FrfOverlay& o) {
  const int w = 520, h = 300, cols = 2;
  const size_t nch = o.measured.size();
  const int rows = static_cast<int>((nch + cols - 1) / cols);
  std::string body;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t c = 0; c < nch; ++c) {
    LinePlot p;
    p.id = "frf" + std::to_string(c);
    p.title = c < o.channel_names.size() ? o.channel_names[c] : "channel " + std::to_string(c + 1);
    p.x_label = "frequency (Hz)";
    p.y_label = "|H| " + o.unit;
    p.log_y = true;
    p.width_px = w;
    p.height_px = h;
    Series all{"measured (not compared)", o.f_hz, {}, "#bbbbbb", 1.0};
    Series used{"measured, coherence >= 0.8", o.f_hz, {}, "#000000", 1.6};
    Series bf{o.before_label, o.f_hz, {}, "#1f77b4", 1.2, true};
    Series af{o.after_label, o.f_hz, {}, "#d62728", 1.6};
    for (size_t i = 0; i < o.f_hz.size(); ++i) {
      const double m = std::abs(o.measured[c][i]);
      all.y.push_back(m);
      used.y.push_back(o.compared[c][i] ? m : nan);
      bf.y.push_back(c < o.before.size() ? std::abs(o.before[c][i]) : nan);
      af.y.push_back(c < o.after.size() ? std::abs(o.after[c][i]) : nan);
    }
    p.series = {all, used, bf, af};
    std::string svg = render_line_plot(p);
    const int x = static_cast<int>(c % cols) * w, y = 30 + static_cast<int>(c / cols) * h;
    const size_t at = svg.find("<svg");
    if (at != std::string::npos) svg.insert(at + 4, " x=\"" + std::to_string(x) + "\" y=\"" + std::to_string(y) + "\"");
    body += svg + "\n";
  }
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                    std::to_string(cols * w) + "\" height=\"" + std::to_string(30 + rows * h) + "\">\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"10\" y=\"20\" font-family=\"sans-serif\" font-size=\"15\">" +
         escape_xml(o.title) + "</text>\n";
  return out + body + "</svg>\n";
}

}  // namespace amb::host::report
