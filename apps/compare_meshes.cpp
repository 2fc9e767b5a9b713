#include "apps/compare_meshes.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "apps/commands.hpp"
#include "io/input_error.hpp"
#include "io/mesh_io.hpp"
#include "render/vertex_metrics.hpp"

namespace lhr::app {

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

bool is_mesh_file(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".ply";
}

int compare_meshes(const std::filesystem::path& mesh_path, const std::filesystem::path& reference_path, bool json) {
  const RawMesh mesh = read_raw_mesh(mesh_path);
  const RawMesh reference = read_raw_mesh(reference_path);
  VertexMetrics m;
  try {
    m = compare_vertex_radiance(mesh, reference);
  } catch (const std::invalid_argument& e) {
    throw InputError(mesh_path, std::string(e.what()) + " (reference " + reference_path.string() + ")");
  }
  if (json) {
    nlohmann::json doc;
    doc["mesh"] = mesh_path.string();
    doc["reference"] = reference_path.string();
    doc["vertices"] = m.vertices;
    doc["floor"] = m.floor;
    doc["p50"] = finite_or_null(m.p50);
    doc["p95"] = finite_or_null(m.p95);
    doc["max"] = finite_or_null(m.max);
    doc["worst_vertex"] = m.worst_vertex;
    doc["within_10_percent"] = m.within_10;
    doc["within_15_percent"] = m.within_15;
    doc["mean_ratio"] = finite_or_null(m.mean_ratio);
    if (m.has_noise) {
      doc["reference_noise_p50"] = m.noise_p50;
      doc["beyond_3_sigma_percent"] = m.beyond_3_sigma;
    }
    std::cout << doc.dump(2) << "\n";
    return kExitOk;
  }
  std::ostringstream s;
  s << std::fixed;
  s << "vertices compared " << m.vertices << " (relative luminance error |Y-Yref| / max(Yref, " << std::setprecision(4)
    << m.floor << "), the floor 1 % of the mean Yref)\n";
  s << std::setprecision(2) << "within 10 %       " << m.within_10 << " %\n";
  s << "within 15 %       " << m.within_15 << " %\n";
  s << std::setprecision(4) << "p50               " << m.p50 << "\n";
  s << "p95               " << m.p95 << "\n";
  s << "max               " << m.max << " (vertex " << m.worst_vertex << ")\n";
  s << "mean ratio        " << m.mean_ratio << " (sum Y / sum Yref)\n";
  if (m.has_noise) {
    s << "reference noise   " << m.noise_p50 << " (median standard error, same units as p50)\n";
    s << std::setprecision(2) << "beyond 3 sigma    " << m.beyond_3_sigma
      << " % of vertices (about 0.3 % if the only difference is the reference's noise)\n";
  }
  std::cout << s.str();
  return kExitOk;
}

}  // namespace lhr::app
