#include "queries/inspection/inspection_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "queries/distance/deviation_report.h"

namespace queries {
namespace {

/// `text` with the characters HTML gives a meaning escaped.
std::string html(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string base64(const void* data, size_t size) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* b = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (size_t i = 0; i < size; i += 3) {
    const uint32_t v =
        uint32_t(b[i]) << 16 | (i + 1 < size ? uint32_t(b[i + 1]) << 8 : 0u) | (i + 2 < size ? uint32_t(b[i + 2]) : 0u);
    out += digits[v >> 18 & 63];
    out += digits[v >> 12 & 63];
    out += i + 1 < size ? digits[v >> 6 & 63] : '=';
    out += i + 2 < size ? digits[v & 63] : '=';
  }
  return out;
}

std::string css_colour(const glm::dvec3& c) {
  return fmt::format("rgb({},{},{})", int(std::lround(255 * c.x)), int(std::lround(255 * c.y)),
                     int(std::lround(255 * c.z)));
}

/// The histogram of the inliers' deviations over [-range, range] as SVG, bars in their colours,
/// the bands' limits drawn.
std::string histogram_svg(const InspectResult& r, double green, double range) {
  constexpr int bins = 60, width = 640, height = 220, left = 50, bottom = 30;
  std::vector<long long> count(bins, 0);
  long long beyond_low = 0, beyond_high = 0;
  for (size_t k = 0; k < r.points.size(); ++k) {
    if (r.outlier[k] || !std::isfinite(r.deviation[k])) continue;
    const double d = r.deviation[k];
    if (d < -range) {
      ++beyond_low;
    } else if (d > range) {
      ++beyond_high;
    } else {
      const int b = std::clamp(int((d + range) / (2.0 * range) * bins), 0, bins - 1);
      ++count[size_t(b)];
    }
  }
  const long long top = std::max<long long>(1, *std::max_element(count.begin(), count.end()));
  const double bar = double(width - left - 10) / bins, plot = height - bottom - 10;
  std::string svg =
      fmt::format("<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' role='img' aria-label='histogram'>",
                  width, height);
  for (int b = 0; b < bins; ++b) {
    const double centre = -range + (b + 0.5) * 2.0 * range / bins;
    const double h = plot * double(count[size_t(b)]) / double(top);
    svg += fmt::format("<rect x='{:.1f}' y='{:.1f}' width='{:.1f}' height='{:.1f}' fill='{}'/>", left + b * bar,
                       10 + plot - h, bar * 0.9, h, css_colour(deviation_colour(centre, green, range)));
  }
  for (const BandVerdicts& band : r.bands)
    for (const double x : {-band.within, band.within}) {
      if (std::abs(x) > range) continue;
      const double px = left + (x + range) / (2.0 * range) * (width - left - 10);
      svg += fmt::format("<line x1='{0:.1f}' x2='{0:.1f}' y1='10' y2='{1:.1f}' stroke='#333' stroke-dasharray='4 3'/>",
                         px, 10 + plot);
    }
  svg += fmt::format("<line x1='{0}' x2='{1}' y1='{2:.1f}' y2='{2:.1f}' stroke='#333'/>", left, width - 10, 10 + plot);
  for (const double x : {-range, 0.0, range}) {
    const double px = left + (x + range) / (2.0 * range) * (width - left - 10);
    svg += fmt::format("<text x='{:.1f}' y='{}' font-size='11' text-anchor='middle'>{:.3g}</text>", px, height - 10, x);
  }
  svg += fmt::format("<text x='5' y='20' font-size='11'>{}</text>", top);
  svg += "</svg>";
  if (beyond_low + beyond_high > 0)
    svg += fmt::format("<p class='note'>{} inliers below &minus;{:.3g} and {} above {:.3g} are not drawn.</p>",
                       beyond_low, range, beyond_high, range);
  return svg;
}

}  // namespace

std::string inspection_report_html(const InspectionReportInputs& in) {
  if (!in.result || !in.part || in.three_js.empty())
    throw std::invalid_argument("inspection_report_html: a result, a part and three.js are needed");
  const InspectResult& r = *in.result;
  const InspectStatistics& s = r.stats;
  const double green = r.bands.empty() ? r.tolerance : r.bands.front().within;
  const double range = in.range > 0.0    ? in.range
                       : r.bands.empty() ? std::max(std::abs(s.min), std::abs(s.max))
                                         : 2.0 * r.bands.back().within;
  // The points drawn (evenly spread), as float32 positions and byte colours; the part's triangles.
  const size_t n = r.points.size(),
               step = std::max<size_t>(1, (n + in.max_points - 1) / std::max<size_t>(1, in.max_points));
  std::vector<float> points;
  std::vector<uint8_t> colours;
  for (size_t k = 0; k < n; k += step) {
    for (int a = 0; a < 3; ++a) points.push_back(float(r.points[k][a]));
    const glm::dvec3 c = deviation_colour(r.outlier[k] ? std::nan("") : r.deviation[k], green, range);
    for (int a = 0; a < 3; ++a) colours.push_back(uint8_t(std::lround(255.0 * c[a])));
  }
  std::vector<float> vertices;
  for (const glm::dvec3& p : in.part->positions)
    for (int a = 0; a < 3; ++a) vertices.push_back(float(p[a]));
  std::vector<uint32_t> triangles;
  for (const glm::ivec3& t : in.part->triangles)
    for (int a = 0; a < 3; ++a) triangles.push_back(uint32_t(t[a]));

  const bool certain = r.failure().empty();
  std::string o;
  o += "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>\n";
  o += fmt::format("<title>Inspection of {} against {}</title>\n", html(in.scan), html(in.model));
  o += "<style>body{font-family:sans-serif;margin:1.5em;color:#222}h1{font-size:1.4em}"
       "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}"
       "th{background:#eee}.ok{color:#176b2c;font-weight:bold}.no{color:#a31515;font-weight:bold}"
       "#view{width:100%;height:520px;border:1px solid #bbb;background:#fafafa}"
       ".swatch{display:inline-block;width:1.2em;height:0.9em;margin-right:0.3em;vertical-align:middle}"
       ".note{color:#555;font-size:0.9em}</style></head><body>\n";
  o += fmt::format("<h1>Inspection of <code>{}</code> against <code>{}</code></h1>\n", html(in.scan), html(in.model));
  o += certain ? fmt::format(
                     "<p id='certificate' class='ok'>Certified: every verdict of the {} inliers holds whatever "
                     "the bounds (deviations within {:.3g} {}).</p>\n",
                     s.inliers, r.tolerance, html(in.unit))
               : fmt::format("<p id='certificate' class='no'>Not certain: {}.</p>\n", html(r.failure()));
  o += "<div id='view'></div><p class='note'>Drag to turn the part, wheel to zoom. Grey: outliers and points "
       "without an answer.</p>\n";
  // Legend
  o += "<h2>Bands</h2><p>";
  o += fmt::format("<span class='swatch' style='background:{}'></span>within {:.3g} {} &nbsp; ",
                   css_colour(deviation_colour(0.0, green, range)), green, html(in.unit));
  o += fmt::format("<span class='swatch' style='background:{}'></span>above &nbsp; ",
                   css_colour(deviation_colour(range, green, range)));
  o += fmt::format("<span class='swatch' style='background:{}'></span>below (inside) &nbsp; ",
                   css_colour(deviation_colour(-range, green, range)));
  o += fmt::format("full colour at &plusmn;{:.3g} {}</p>\n", range, html(in.unit));
  o += "<table id='bands'><tr><th>band</th><th>within</th><th>above</th><th>below</th><th>certainly within</th>"
       "<th>certainly outside</th><th>undecided</th></tr>\n";
  for (const BandVerdicts& b : r.bands)
    o += fmt::format(
        "<tr><td>&plusmn;{:.4g}</td><td>{:.2f} %</td><td>{:.2f} %</td><td>{:.2f} %</td><td>{}</td>"
        "<td>{}</td><td>{}</td></tr>\n",
        b.within, 100 * b.share_within, 100 * b.share_above, 100 * b.share_below, b.certainly_within,
        b.certainly_outside, b.undecided);
  o += "</table>\n<h2>Histogram</h2>\n" + histogram_svg(r, green, range) + "\n";
  o += "<h2>Statistics</h2><table id='statistics'><tr>";
  for (const char* h : {"points", "inliers", "outliers", "no answer", "min", "max", "mean", "&sigma;", "rms"})
    o += fmt::format("<th>{}</th>", h);
  o += fmt::format(
      "</tr><tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.4g}</td><td>{:.4g}</td><td>{:.4g}</td>"
      "<td>{:.4g}</td><td>{:.4g}</td></tr></table>\n",
      s.points, s.inliers, s.outliers, s.not_found, s.min, s.max, s.mean, s.sigma, s.rms);
  o += "<p>Percentiles: ";
  for (size_t i = 0; i < s.percentiles.size(); ++i)
    o += fmt::format("{}{:g} %: {:.4g}", i ? ", " : "", InspectStatistics::kPercentiles[i], s.percentiles[i]);
  o += fmt::format(" ({}; {}).</p>\n", html(in.unit), r.signed_values ? "signed: negative inside" : "unsigned");
  o += "<h2>Alignment</h2>";
  if (r.aligned)
    o += fmt::format("<p>Best fit {} in {} rounds on {} points; rms {:.4g} {}{}.</p>",
                     r.alignment.converged ? "converged" : "FAILED", r.alignment.iterations, r.alignment.points_used,
                     r.alignment.rms, html(in.unit), r.alignment.converged ? "" : ": " + html(r.alignment.problem));
  else
    o += "<p>No best fit: the scan placed as given.</p>";
  o += "<table id='matrix'>";
  for (int row = 0; row < 4; ++row) {
    o += "<tr>";
    for (int c = 0; c < 4; ++c) o += fmt::format("<td>{:.9g}</td>", r.alignment.matrix[c][row]);
    o += "</tr>";
  }
  o += "</table><p class='note'>Scan into model coordinates.</p>\n";
  o += "<script>\n" + in.three_js + "\n</script>\n";
  o += fmt::format("<script>const DATA={{points:'{}',colours:'{}',vertices:'{}',triangles:'{}'}};</script>\n",
                   base64(points.data(), points.size() * 4), base64(colours.data(), colours.size()),
                   base64(vertices.data(), vertices.size() * 4), base64(triangles.data(), triangles.size() * 4));
  o += R"JS(<script>
(function () {
  function bytes(b64) {
    const s = atob(b64), a = new Uint8Array(s.length);
    for (let i = 0; i < s.length; ++i) a[i] = s.charCodeAt(i);
    return a;
  }
  const view = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer({antialias: true});
  renderer.setSize(view.clientWidth, view.clientHeight);
  renderer.setClearColor(0xfafafa);
  view.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const part = new THREE.BufferGeometry();
  part.setAttribute('position', new THREE.BufferAttribute(new Float32Array(bytes(DATA.vertices).buffer), 3));
  part.setIndex(new THREE.BufferAttribute(new Uint32Array(bytes(DATA.triangles).buffer), 1));
  part.computeVertexNormals();
  scene.add(new THREE.Mesh(part, new THREE.MeshLambertMaterial({color: 0xb8b8c0, side: THREE.DoubleSide,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1})));
  const cloud = new THREE.BufferGeometry();
  cloud.setAttribute('position', new THREE.BufferAttribute(new Float32Array(bytes(DATA.points).buffer), 3));
  cloud.setAttribute('color', new THREE.BufferAttribute(bytes(DATA.colours), 3, true));
  scene.add(new THREE.Points(cloud, new THREE.PointsMaterial({size: 3, sizeAttenuation: false, vertexColors: true})));
  scene.add(new THREE.AmbientLight(0xffffff, 0.5));
  const light = new THREE.DirectionalLight(0xffffff, 0.7);
  scene.add(light);
  part.computeBoundingSphere();
  const centre = part.boundingSphere.center, radius = part.boundingSphere.radius || 1;
  const camera = new THREE.PerspectiveCamera(35, view.clientWidth / view.clientHeight, radius / 100, radius * 100);
  let yaw = 0.8, pitch = 0.5, distance = 3.2 * radius;
  function draw() {
    camera.position.set(centre.x + distance * Math.cos(pitch) * Math.cos(yaw),
                        centre.y + distance * Math.cos(pitch) * Math.sin(yaw), centre.z + distance * Math.sin(pitch));
    camera.up.set(0, 0, 1);
    camera.lookAt(centre);
    light.position.copy(camera.position);
    renderer.render(scene, camera);
  }
  let drag = null;
  renderer.domElement.addEventListener('mousedown', e => { drag = [e.clientX, e.clientY]; });
  window.addEventListener('mouseup', () => { drag = null; });
  window.addEventListener('mousemove', e => {
    if (!drag) return;
    yaw -= (e.clientX - drag[0]) * 0.01;
    pitch = Math.max(-1.5, Math.min(1.5, pitch + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw();
  });
  renderer.domElement.addEventListener('wheel', e => {
    e.preventDefault();
    distance *= Math.exp(e.deltaY * 0.001);
    draw();
  });
  draw();
  document.body.setAttribute('data-rendered', 'yes');
})();
</script>
</body></html>
)JS";
  return o;
}

}  // namespace queries
