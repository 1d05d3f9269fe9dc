#include "nurbs/io/iges_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "nurbs/io/iges_faces.h"
#include "nurbs/io/input_file.h"
#include "nurbs/io/read_error.h"
#include "nurbs/model_ops.h"

namespace nurbs::io {
namespace {

// Types the reader converts or deliberately ignores; everything else is counted as skipped.
bool is_read_type(int type) {
  switch (type) {
    case 0:
    case 100:
    case 102:
    case 104:
    case 110:
    case 124:
    case 126:
    case 128:
    case 141:
    case 142:
    case 143:
    case 144:
    case 186:
    case 108:  // bounded planes (form 1) are faces; a 108 under a 144 is read with it
    case 120:  // 120, 122, 190-198: analytic surfaces, read for the 144 and 510 faces on them (iges_analytic.h)
    case 122:
    case 190:
    case 192:
    case 194:
    case 196:
    case 198:
    case 308:  // subfigures: their instances (408) place copies of the definition (308)
    case 314:
    case 402:
    case 408:
    case 406:
    case 502:
    case 504:
    case 508:
    case 510:
    case 514:
      return true;
    default:
      return false;
  }
}

class ModelBuilder {
 public:
  ModelBuilder(const IgesFile& file, const IgesReadOptions& options, IgesReadLog& log)
      : file_(file), g_(file), faces_(g_, options, log), log_(log), used_(file.entries.size(), 0) {}

  std::vector<Body> build();
  /// After build(): entries of types the reader does not convert that nothing read used, by type.
  [[nodiscard]] std::map<int, int> skipped() const;
  /// After build(): the face entities tried (read or dropped) and those dropped, with the reason.
  [[nodiscard]] int faces_tried() const { return faces_tried_; }
  [[nodiscard]] const std::vector<DroppedFace>& dropped() const { return dropped_; }
  [[nodiscard]] const std::vector<std::string>& geometry_warnings() const { return g_.warnings(); }

 private:
  size_t index(int de) const { return static_cast<size_t>(de - 1) / 2; }
  void add_face(Body& body, int de, const glm::dmat4& parent, bool reversed = false);
  void add_shell(Body& body, int de, const glm::dmat4& parent, bool reversed = false);
  void add_solid(std::vector<Body>& bodies, int de, const glm::dmat4& parent, const std::string& prefix);
  void add_instance(std::vector<Body>& bodies, int de, const glm::dmat4& parent, const std::string& prefix,
                    int depth);
  void drop(int de, const std::string& reason);

  const IgesFile& file_;
  IgesGeometry g_;
  IgesFaces faces_;
  IgesReadLog& log_;
  std::vector<char> used_;  // entry already part of a body (shells, faces, their surfaces)
  std::vector<char> instanced_;  // entry listed by a subfigure definition (308) that a 408 places
  std::vector<char> face_surface_;  // entry is the surface of a face entity (144, 143, 510)
  int faces_tried_ = 0;
  std::vector<DroppedFace> dropped_;
};

void ModelBuilder::add_face(Body& body, int de, const glm::dmat4& parent, bool reversed) {
  used_[index(de)] = 1;
  ++faces_tried_;
  try {
    body.faces.push_back(faces_.face(de, parent));
    body.faces.back().reversed = reversed;
  } catch (const UnsupportedEntity& u) {
    drop(de, fmt::format("it needs D{} of unsupported type {}", u.de, u.type));
  } catch (const SkipFace& s) {
    drop(de, s.reason);
  }
}

void ModelBuilder::drop(int de, const std::string& reason) {
  log_.warnings.push_back(fmt::format("face D{} dropped: {}", de, reason));
  dropped_.push_back({fmt::format("D{}", de), reason});
}

// 514: N, then N pairs (FACE pointer to a 510, OF orientation flag: 1 = the face's outward side is
// its surface's normal side, IGES 5.3 "Shell Entity (Type 514)"). `reversed`: the shell's own flag
// in its 186 is 0, which turns every face of it round (as OpenCASCADE's TransferManifoldSolid does).
void ModelBuilder::add_shell(Body& body, int de, const glm::dmat4& parent, bool reversed) {
  used_[index(de)] = 1;
  EntityParams p(file_, file_.entry(de));
  const int n = p.integer(1, 1, std::max(1, p.size() / 2), "number of faces N");
  std::vector<std::pair<int, bool>> faces;  // 510, reversed
  for (int k = 0; k < n; ++k) {
    const int face = g_.expect(p, 2 + 2 * k, {510}, "a face");
    faces.emplace_back(face, (p.integer(3 + 2 * k, 0, 1, "orientation flag") == 0) != reversed);
  }
  p.check_trailing(1 + 2 * n);
  const glm::dmat4 m = parent * g_.transform(de);
  for (auto [f, r] : faces) add_face(body, f, m, r);
}

// 186: SHELL, SOF, N, then N pairs (VOID shell, VOF): one body per solid.
void ModelBuilder::add_solid(std::vector<Body>& bodies, int de, const glm::dmat4& parent, const std::string& prefix) {
  const IgesDirectoryEntry& e = file_.entry(de);
  used_[index(de)] = 1;
  EntityParams p(file_, e);
  std::vector<std::pair<int, bool>> shells;  // 514, reversed (its flag SOF / VOF is 0)
  const int shell = g_.expect(p, 1, {514}, "a shell");
  shells.emplace_back(shell, p.integer(2, 0, 1, "orientation flag SOF") == 0);
  const int n = p.integer(3, 0, std::max(0, p.size() / 2), "number of void shells N");
  for (int k = 0; k < n; ++k) {
    const int void_shell = g_.expect(p, 4 + 2 * k, {514}, "a shell");
    shells.emplace_back(void_shell, p.integer(5 + 2 * k, 0, 1, "orientation flag VOF") == 0);
  }
  p.check_trailing(3 + 2 * n);
  Body body{prefix + (e.label.empty() ? fmt::format("solid D{}", e.de) : e.label), {}, glm::dmat4(1.0), {}};
  body.closed = true;
  for (auto [s, r] : shells) add_shell(body, s, parent * g_.transform(e.de), r);
  bodies.push_back(std::move(body));
}

// 408: DE (its 308), X, Y, Z, S (scale, 1 when left empty); 308: DEPTH, NAME, N, DE(1..N). The
// definition's entities are placed by M * T(X, Y, Z) * S, M the 408's matrix (IGES 5.3, "Singular
// Subfigure Instance Entity (Type 408)"); faces, shells and solids among them are read there, one
// body per instance; nested instances compose.
void ModelBuilder::add_instance(std::vector<Body>& bodies, int de, const glm::dmat4& parent, const std::string& prefix,
                                int depth) {
  constexpr int kMaxSubfigureDepth = 16;
  used_[index(de)] = 1;
  if (depth > kMaxSubfigureDepth)
    g_.fail(de, fmt::format("subfigure instances nest deeper than {} (a definition that holds itself?)",
                            kMaxSubfigureDepth));
  EntityParams p(file_, file_.entry(de));
  const int def = g_.expect(p, 1, {308}, "a subfigure definition");
  const glm::dvec3 move(p.real(2), p.real(3), p.real(4));
  const bool scaled = p.size() >= 5 && !p.string(5).empty();
  const double scale = scaled ? p.real(5) : 1.0;
  if (!(scale > 0.0)) p.fail(5, fmt::format("scale factor {} is not positive", scale));
  p.check_trailing(scaled ? 5 : 4);
  glm::dmat4 place(scale);
  place[3] = glm::dvec4(move, 1.0);
  const glm::dmat4 m = parent * g_.transform(de) * place;
  used_[index(def)] = 1;
  EntityParams d(file_, file_.entry(def));
  const int n = d.integer(3, 0, std::max(0, d.size() - 3), "number of entities N");
  std::string title = d.size() >= 2 ? d.string(2) : "";
  if (title.empty()) title = file_.entry(def).label.empty() ? "subfigure" : file_.entry(def).label;
  const std::string name = prefix + fmt::format("{} D{}/", title, de);
  Body loose{name + "faces", {}, glm::dmat4(1.0), {}};
  for (int k = 0; k < n; ++k) {
    const int member = d.pointer(4 + k);
    const IgesDirectoryEntry& e = file_.entry(member);
    if (e.type == 408)
      add_instance(bodies, member, m, name, depth + 1);
    else if (e.type == 186)
      add_solid(bodies, member, m, name);
    else if (e.type == 514) {
      Body shell{name + (e.label.empty() ? fmt::format("shell D{}", e.de) : e.label), {}, glm::dmat4(1.0), {}};
      add_shell(shell, member, m);
      bodies.push_back(std::move(shell));
    } else if (e.type == 144 || e.type == 143 || e.type == 510 || (e.type == 128 && !face_surface_[index(member)]) ||
               (e.type == 108 && e.form == 1))
      add_face(loose, member, m);
  }
  d.check_trailing(3 + n);
  if (!loose.faces.empty()) bodies.push_back(std::move(loose));
}

std::vector<Body> ModelBuilder::build() {
  std::vector<Body> bodies;
  // The entities of subfigure definitions that an instance places are read there, not where the
  // definition lists them; a definition no instance places is read as it stands.
  instanced_.assign(file_.entries.size(), 0);
  face_surface_.assign(file_.entries.size(), 0);
  for (const IgesDirectoryEntry& e : file_.entries) {
    if (e.type != 408) continue;
    EntityParams p(file_, e);
    const int def = g_.expect(p, 1, {308}, "a subfigure definition");
    EntityParams d(file_, file_.entry(def));
    const int n = d.integer(3, 0, std::max(0, d.size() - 3), "number of entities N");
    for (int k = 0; k < n; ++k) instanced_[index(d.pointer(4 + k))] = 1;
  }
  // Surfaces of face entities are not faces of their own.
  for (const IgesDirectoryEntry& e : file_.entries)
    if (e.type == 144 || e.type == 143 || e.type == 510)
      if (int s = faces_.surface_pointer(e.de); s != 0) used_[index(s)] = face_surface_[index(s)] = 1;
  for (const IgesDirectoryEntry& e : file_.entries)
    if (e.type == 186 && !instanced_[index(e.de)]) add_solid(bodies, e.de, glm::dmat4(1.0), "");
  // Instances before the shells and faces outside solids: the shells and faces of the solids they
  // place are then used, and not read a second time where the definitions hold them.
  for (const IgesDirectoryEntry& e : file_.entries)
    if (e.type == 408 && !instanced_[index(e.de)]) add_instance(bodies, e.de, glm::dmat4(1.0), "", 0);
  // Instances that only definitions placed by one another list (a cycle) are reached from here, and
  // their nesting fails the read.
  for (const IgesDirectoryEntry& e : file_.entries)
    if (e.type == 408 && !used_[index(e.de)]) add_instance(bodies, e.de, glm::dmat4(1.0), "", 0);
  for (const IgesDirectoryEntry& e : file_.entries) {
    if (e.type != 514 || used_[index(e.de)] || instanced_[index(e.de)]) continue;
    Body body{e.label.empty() ? fmt::format("shell D{}", e.de) : e.label, {}, glm::dmat4(1.0), {}};
    add_shell(body, e.de, glm::dmat4(1.0));
    bodies.push_back(std::move(body));
  }
  // Faces outside shells; a bare 128 is a face when no face uses it and it is not physically dependent.
  Body loose{"faces", {}, glm::dmat4(1.0), {}};
  for (const IgesDirectoryEntry& e : file_.entries) {
    if (used_[index(e.de)] || instanced_[index(e.de)]) continue;
    const bool independent = e.subordinate() != 1 && e.subordinate() != 3;
    const bool face = e.type == 144 || e.type == 143 || e.type == 510 || (e.type == 128 && independent) ||
                      (e.type == 108 && e.form == 1 && independent);
    if (face) add_face(loose, e.de, glm::dmat4(1.0));
  }
  if (!loose.faces.empty()) bodies.push_back(std::move(loose));
  log_.ranges_restricted = g_.ranges_restricted();
  // Loops are finished once the model size is known: gaps are judged on the surface relative to it.
  // A size that cannot scale tolerances (validate_model_size) closes no gap on the surface.
  Model sized;
  sized.bodies = std::move(bodies);
  double size = model_size(sized);
  if (!validate_model_size(size).empty()) size = 0.0;
  for (Body& b : sized.bodies) {
    for (TrimmedSurface& f : b.faces) faces_.finish(f, size);
    const size_t before = b.faces.size();
    std::erase_if(b.faces, [&](const TrimmedSurface& f) {
      if (trims_evaluable(f)) return false;
      dropped_.push_back({fmt::format("D{}", f.face_id), f.trim_problem});
      return true;
    });
    b.lose_faces(before - b.faces.size());
  }
  return std::move(sized.bodies);
}

}  // namespace

std::map<int, int> ModelBuilder::skipped() const {
  std::map<int, int> out;
  for (const IgesDirectoryEntry& e : file_.entries)
    if (!is_read_type(e.type) && !g_.referenced(e.de)) ++out[e.type];
  return out;
}

Model read_iges_text(std::string text, const std::string& name, const IgesReadOptions& options, IgesReadLog* log) {
  IgesReadLog local;
  IgesReadLog& lg = log ? *log : local;
  const IgesFile file = parse_iges_file(std::move(text), name);
  lg.global = file.global;
  Model model;
  model.source = name;
  model.unit_scale_to_mm = file.global.unit_scale_to_mm;
  model.resolution = std::isfinite(file.global.resolution) ? std::max(file.global.resolution, 0.0) : 0.0;
  ModelBuilder builder(file, options, lg);
  model.bodies = builder.build();
  model.skipped_entities = builder.skipped();
  model.faces_in_file = builder.faces_tried();
  model.dropped_faces = builder.dropped();
  model.read_warnings.insert(model.read_warnings.begin(), file.global.warnings.begin(), file.global.warnings.end());
  model.read_warnings.insert(model.read_warnings.end(), builder.geometry_warnings().begin(),
                             builder.geometry_warnings().end());
  if (options.convert_to_mm && model.unit_scale_to_mm != 1.0) {
    for (Body& b : model.bodies)
      for (TrimmedSurface& f : b.faces)
        for (glm::dvec3& q : f.surface.points) q *= model.unit_scale_to_mm;
    model.resolution *= model.unit_scale_to_mm;
    model.unit_scale_to_mm = 1.0;
  }
  return model;
}

Model read_iges(const std::filesystem::path& path, const IgesReadOptions& options, IgesReadLog* log) {
  return read_iges_text(read_input_file(path), path.string(), options, log);
}

}  // namespace nurbs::io
