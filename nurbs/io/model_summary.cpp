#include "nurbs/io/model_summary.h"

#include <fmt/format.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <limits>
#include <nlohmann/json.hpp>

#include "nurbs/model_ops.h"

namespace nurbs::io {

FaceSummary summarize_face(const TrimmedSurface& f) {
  FaceSummary fs;
  fs.face_id = f.face_id;
  fs.name = f.name;
  fs.degree_u = f.surface.degree_u;
  fs.degree_v = f.surface.degree_v;
  fs.count_u = f.surface.count_u;
  fs.count_v = f.surface.count_v;
  fs.rational = f.surface.rational();
  for (const TrimLoop& l : f.loops) {
    (l.outer ? fs.outer_loops : fs.inner_loops) += 1;
    fs.trim_curves += static_cast<int>(l.curves.size());
  }
  return fs;
}

ModelSummary summarize(const Model& model) {
  ModelSummary s;
  s.source = model.source;
  s.unit_scale_to_mm = model.unit_scale_to_mm;
  s.bodies = static_cast<int>(model.bodies.size());
  s.skipped_entities = model.skipped_entities;
  s.skipped_types = model.skipped_types;
  s.faces_in_file = model.faces_in_file;
  s.faces_dropped = model.dropped_faces;
  s.read_warnings = model.read_warnings;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = model.bodies[b];
    s.body_list.push_back({body.name, body.instance, static_cast<int>(body.faces.size())});
    for (const TrimmedSurface& f : body.faces) {
      FaceSummary fs = summarize_face(f);
      fs.body = static_cast<int>(b);
      for (const glm::dvec3& p : f.surface.points) {
        const glm::dvec3 q(body.transform * glm::dvec4(p, 1.0));
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
      }
      s.faces += 1;
      s.trimmed_faces += f.loops.empty() ? 0 : 1;
      s.rational_faces += fs.rational ? 1 : 0;
      s.control_points += static_cast<int>(f.surface.points.size());
      s.max_degree_u = std::max(s.max_degree_u, fs.degree_u);
      s.max_degree_v = std::max(s.max_degree_v, fs.degree_v);
      s.outer_loops += fs.outer_loops;
      s.inner_loops += fs.inner_loops;
      s.trim_curves += fs.trim_curves;
      s.face_list.push_back(std::move(fs));
    }
  }
  if (s.control_points > 0) {
    s.bbox_min = lo;
    s.bbox_max = hi;
    const Box box = model_box(model);
    s.sampled_min = box.min;
    s.sampled_max = box.max;
    s.size = box.diagonal();
    s.control_size = Box{lo, hi}.diagonal();
  }
  return s;
}

std::string to_text(const ModelSummary& s, bool per_face) {
  std::string out = fmt::format("source: {}\nunit: {} mm\nbodies: {}\n", s.source, s.unit_scale_to_mm, s.bodies);
  // "With trim loops" counts every face with a loop, also one on its surface's natural boundary
  // (every face of a B-rep file): other kernels count as trimmed only faces cut inside it.
  out += fmt::format("faces: {} ({} with trim loops, {} rational)\n", s.faces, s.trimmed_faces, s.rational_faces);
  // Faces the file has but the model lacks come first: every answer on the model is partial.
  if (s.faces_in_file >= 0)
    out += fmt::format("faces in file: {} ({} dropped)\n", s.faces_in_file, s.faces_dropped.size());
  for (const DroppedFace& d : s.faces_dropped) out += fmt::format("dropped face {}: {}\n", d.entity, d.reason);
  for (const std::string& w : s.read_warnings) out += fmt::format("read warning: {}\n", w);
  out += fmt::format("max degree: {} x {}\ncontrol points: {}\n", s.max_degree_u, s.max_degree_v, s.control_points);
  out += fmt::format("trim loops: {} outer, {} inner, {} curves\n", s.outer_loops, s.inner_loops, s.trim_curves);
  out += fmt::format("control-point box: [{:.6g} {:.6g} {:.6g}] - [{:.6g} {:.6g} {:.6g}]\n", s.bbox_min.x, s.bbox_min.y,
                     s.bbox_min.z, s.bbox_max.x, s.bbox_max.y, s.bbox_max.z);
  out += fmt::format("sampled box: [{:.6g} {:.6g} {:.6g}] - [{:.6g} {:.6g} {:.6g}]\n", s.sampled_min.x, s.sampled_min.y,
                     s.sampled_min.z, s.sampled_max.x, s.sampled_max.y, s.sampled_max.z);
  out += fmt::format(
      "model size: {:.6g} (sampled box diagonal, a lower estimate; relative tolerances refer to it; the "
      "control-point box diagonal {:.6g} bounds it above)\n",
      s.size, s.control_size);
  out += "skipped entities:";
  if (s.skipped_entities.empty() && s.skipped_types.empty()) out += " none";
  for (auto [type, count] : s.skipped_entities) out += fmt::format(" {}x{}", type, count);
  for (const auto& [type, count] : s.skipped_types) out += fmt::format(" {}x{}", type, count);
  out += '\n';
  if (s.body_list.size() > 1 || (s.body_list.size() == 1 && !s.body_list.front().instance.empty()))
    for (size_t b = 0; b < s.body_list.size(); ++b) {
      const BodySummary& body = s.body_list[b];
      out += fmt::format("body {}: {}, {} faces{}{}\n", b, body.name, body.faces,
                         body.instance.empty() ? "" : ", instance ", body.instance);
    }
  if (per_face)  // numbered as every command numbers faces (0-based, bodies in order); id: the file's
    for (size_t k = 0; k < s.face_list.size(); ++k) {
      const FaceSummary& f = s.face_list[k];
      out += fmt::format(
          "face {} (id {}, body {}{}{}): degree {}x{}, {}x{} points{}, loops {} outer {} inner, {} curves\n", k,
          f.face_id, f.body, f.name.empty() ? "" : ", ", f.name, f.degree_u, f.degree_v, f.count_u, f.count_v,
          f.rational ? ", rational" : "", f.outer_loops, f.inner_loops, f.trim_curves);
    }
  return out;
}

nlohmann::json to_json(const ModelSummary& s) {
  nlohmann::json skipped = nlohmann::json::object();
  for (auto [type, count] : s.skipped_entities) skipped[std::to_string(type)] = count;
  for (const auto& [type, count] : s.skipped_types) skipped[type] = count;
  nlohmann::json dropped = nlohmann::json::array();
  for (const DroppedFace& d : s.faces_dropped) dropped.push_back({{"entity", d.entity}, {"reason", d.reason}});
  nlohmann::json bodies = nlohmann::json::array();
  for (const BodySummary& b : s.body_list)
    bodies.push_back({{"name", b.name}, {"instance", b.instance}, {"faces", b.faces}});
  nlohmann::json faces = nlohmann::json::array();
  for (size_t k = 0; k < s.face_list.size(); ++k) {
    const FaceSummary& f = s.face_list[k];
    faces.push_back({{"body", f.body},
                     {"face", k},
                     {"face_id", f.face_id},
                     {"name", f.name},
                     {"degree", {f.degree_u, f.degree_v}},
                     {"control_points", {f.count_u, f.count_v}},
                     {"rational", f.rational},
                     {"outer_loops", f.outer_loops},
                     {"inner_loops", f.inner_loops},
                     {"trim_curves", f.trim_curves}});
  }
  return {{"source", s.source},
          {"unit_scale_to_mm", s.unit_scale_to_mm},
          {"bodies", s.bodies},
          {"body_list", bodies},
          {"faces", s.faces},
          {"faces_in_file", s.faces_in_file},
          {"faces_dropped", dropped},
          {"read_warnings", s.read_warnings},
          {"trimmed_faces", s.trimmed_faces},
          {"rational_faces", s.rational_faces},
          {"control_points", s.control_points},
          {"max_degree", {s.max_degree_u, s.max_degree_v}},
          {"trim_loops", {{"outer", s.outer_loops}, {"inner", s.inner_loops}, {"curves", s.trim_curves}}},
          {"control_bbox",
           {{"min", {s.bbox_min.x, s.bbox_min.y, s.bbox_min.z}}, {"max", {s.bbox_max.x, s.bbox_max.y, s.bbox_max.z}}}},
          {"bbox",
           {{"min", {s.sampled_min.x, s.sampled_min.y, s.sampled_min.z}},
            {"max", {s.sampled_max.x, s.sampled_max.y, s.sampled_max.z}}}},
          {"size", s.size},
          {"size_method", "sampled box diagonal (a lower estimate)"},
          {"control_box_diagonal", s.control_size},
          {"skipped_entities", skipped},
          {"face_list", faces}};
}

}  // namespace nurbs::io
