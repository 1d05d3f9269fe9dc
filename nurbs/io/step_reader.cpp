// STEP B-rep geometry to nurbs::Model: the instances of a parsed Part 21 file (step_file.h) read as
// ISO 10303-42 geometry and topology, placed by the assembly structure of AP203 / AP214 / AP242.
// Units, representations and their placements, products, the model (step_reader_detail.h: the parts).
#include "nurbs/io/step_reader_detail.h"
#include "nurbs/trim_surface_gaps.h"

namespace nurbs::io {
namespace step_detail {

void StepReader::read_units(long context, const StepEntity& from) {
  const StepEntity& c = entity(context, from);
  const StepRecord* units = c.record("GLOBAL_UNIT_ASSIGNED_CONTEXT");
  if (!units) return;
  // SI prefixes of ISO 10303-41.
  static const std::unordered_map<std::string, double> prefixes = {
      {"EXA", 1e18},  {"PETA", 1e15},  {"TERA", 1e12},   {"GIGA", 1e9},   {"MEGA", 1e6},   {"KILO", 1e3},
      {"HECTO", 1e2}, {"DECA", 1e1},   {"DECI", 1e-1},   {"CENTI", 1e-2}, {"MILLI", 1e-3}, {"MICRO", 1e-6},
      {"NANO", 1e-9}, {"PICO", 1e-12}, {"FEMTO", 1e-15}, {"ATTO", 1e-18}};
  // Size of a unit in SI base units (metre, radian), following conversion-based units.
  std::function<double(const StepEntity&, int)> si = [&](const StepEntity& u, int depth) -> double {
    if (depth > kMaxDepth) fail(u, "units nest too deep (a reference cycle?)");
    if (const StepRecord* s = u.record("SI_UNIT")) {
      // (prefix, name) in a complex instance; a simple one leads with NAMED_UNIT's dimensions (*).
      const StepValue& p = param(u, *s, s->params.size() >= 3 ? 1 : 0, "prefix");
      double f = 1.0;
      if (p.kind == Kind::Enum) {
        const auto it = prefixes.find(p.text);
        if (it == prefixes.end()) fail(u, fmt::format("unknown SI prefix .{}.", p.text));
        f = it->second;
      }
      return f;
    }
    if (const StepRecord* cb = u.record("CONVERSION_BASED_UNIT")) {
      const StepEntity& m = entity(ref(u, *cb, 1, "conversion factor"), u);
      if (m.records.empty() || m.records.front().params.size() < 2) fail(m, "is not a measure with unit");
      const StepRecord& mr = m.records.size() == 1 ? m.records.front() : *[&] {
        for (const StepRecord& r : m.records)
          if (r.params.size() >= 2) return &r;
        return &m.records.front();
      }();
      const double value = real(m, mr, 0, "value");
      const StepEntity& base = entity(ref(m, mr, 1, "unit"), m);
      const double x = value * si(base, depth + 1);
      if (!(x > 0) || !std::isfinite(x)) fail(m, "converts to a unit that is not positive");
      return x;
    }
    fail(u, "is a unit nurbsgl does not read");
  };
  for (const StepValue& uv : list(c, param(c, *units, 0, "units"), "units")) {
    const StepEntity& u = entity(ref(c, uv, "unit"), c);
    if (is(u, "LENGTH_UNIT")) length_scale_ = si(u, 0) * 1e3;
    if (is(u, "PLANE_ANGLE_UNIT")) angle_scale_ = si(u, 0);
  }
  if (const StepRecord* g = c.record("GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT"))
    for (const StepValue& uv : list(c, param(c, *g, 0, "uncertainty"), "uncertainty")) {
      const StepEntity& u = entity(ref(c, uv, "uncertainty"), c);
      if (const StepRecord* ur = u.record("UNCERTAINTY_MEASURE_WITH_UNIT")) {
        const double x = real(u, *ur, 0, "uncertainty");
        if (x > 0 && (resolution_ == 0 || x < resolution_)) resolution_ = x;
      }
    }
}

void StepReader::link_representations() {
  // Representations related without a transform share one frame (union-find); with a transform,
  // the component's representation is placed in its assembly's.
  // Product structure first: which representation group belongs to which product definition.
  std::unordered_map<long, long> rep_of_pd;  // PRODUCT_DEFINITION -> shape representation
  std::unordered_map<long, long> pd_of_pds;  // PRODUCT_DEFINITION_SHAPE -> its definition
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    if (const StepRecord* r = e.record("PRODUCT_DEFINITION_SHAPE")) {
      intact(e);  // the assembly structure places the geometry
      if (r->params.size() >= 3 && r->params[2].kind == Kind::Ref) pd_of_pds[id] = r->params[2].ref;
      visited_.insert(id);
    }
  }
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    if (e.record("SHAPE_DEFINITION_REPRESENTATION")) intact(e);
    if (const StepRecord* r = e.record("SHAPE_DEFINITION_REPRESENTATION");
        r && r->params.size() >= 2 && r->params[0].kind == Kind::Ref && r->params[1].kind == Kind::Ref) {
      if (auto it = pd_of_pds.find(r->params[0].ref); it != pd_of_pds.end()) rep_of_pd[it->second] = r->params[1].ref;
      visited_.insert(id);
    }
  }
  struct Placed {
    long rep1, rep2;
    long transform;
    long relationship;
  };
  std::vector<Placed> placed;
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    const StepRecord* r = e.record("REPRESENTATION_RELATIONSHIP");
    if (!r) r = e.record("SHAPE_REPRESENTATION_RELATIONSHIP");
    if (r) intact(e);
    if (!r || r->params.size() < 4) continue;
    visited_.insert(id);
    const long a = ref(e, *r, 2, "rep_1"), b = ref(e, *r, 3, "rep_2");
    entity(a, e), entity(b, e);
    if (const StepRecord* t = e.record("REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION")) {
      placed.push_back({a, b, ref(e, *t, 0, "transformation operator"), id});
    } else {
      const long ga = group(a), gb = group(b);
      if (ga != gb) group_[ga] = gb;
    }
  }
  // CONTEXT_DEPENDENT_SHAPE_REPRESENTATION: relationship -> the usage occurrence it places.
  std::unordered_map<long, long> nauo_of;
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    const StepRecord* r = e.record("CONTEXT_DEPENDENT_SHAPE_REPRESENTATION");
    if (r) intact(e);
    if (!r || r->params.size() < 2 || r->params[0].kind != Kind::Ref || r->params[1].kind != Kind::Ref) continue;
    visited_.insert(id);
    if (auto it = pd_of_pds.find(r->params[1].ref); it != pd_of_pds.end()) nauo_of[r->params[0].ref] = it->second;
  }
  for (const Placed& p : placed) {
    const StepEntity& rel = f_.entities.at(p.relationship);
    const StepEntity& t = entity(p.transform, rel);
    const StepRecord& tr = record(t, "ITEM_DEFINED_TRANSFORMATION");
    const glm::dmat4 m1 = frame_matrix(placement(ref(t, tr, 2, "transform_item_1"), t));
    const glm::dmat4 m2 = frame_matrix(placement(ref(t, tr, 3, "transform_item_2"), t));
    long child = p.rep1, parent = p.rep2;
    glm::dmat4 m = m2 * glm::inverse(m1);  // rep_1's item_1 frame onto rep_2's item_2 frame
    std::string name;
    if (auto it = nauo_of.find(p.relationship); it != nauo_of.end()) {
      const StepEntity& nauo = entity(it->second, rel);
      if (const StepRecord* nr = nauo.record("NEXT_ASSEMBLY_USAGE_OCCURRENCE"); nr && nr->params.size() >= 5) {
        if (nr->params[0].kind == Kind::String) name = nr->params[0].text;
        if (name.empty() && nr->params[1].kind == Kind::String) name = nr->params[1].text;
        // The component is the related product definition: if its shape is rep_2, turn round.
        if (nr->params[4].kind == Kind::Ref)
          if (auto rp = rep_of_pd.find(nr->params[4].ref);
              rp != rep_of_pd.end() && group(rp->second) == group(p.rep2)) {
            std::swap(child, parent);
            m = m1 * glm::inverse(m2);
          }
      }
    }
    parents_[group(child)].push_back({group(parent), m, name});
  }
  // Products by representation group, for body names.
  for (auto [pd, rep] : rep_of_pd) {
    const StepEntity* e = f_.find(pd);
    if (!e || !e->damage.empty()) continue;
    const StepRecord* r = e->record("PRODUCT_DEFINITION");
    if (!r || r->params.size() < 3 || r->params[2].kind != Kind::Ref) continue;
    const StepEntity* formation = f_.find(r->params[2].ref);
    if (!formation || !formation->damage.empty() || formation->records.empty() ||
        formation->records.front().params.size() < 3)
      continue;
    const StepValue& prod = formation->records.front().params[2];
    if (prod.kind == Kind::Ref) product_of_group_.emplace(group(rep), prod.ref);
  }
}

std::vector<Instance> StepReader::instances(long rep, int depth) {
  const long g = group(rep);
  const StepEntity* e = f_.find(rep);
  if (depth > kMaxDepth && e) fail(*e, fmt::format("assemblies nest deeper than {} (a reference cycle?)", kMaxDepth));
  const auto it = parents_.find(g);
  if (it == parents_.end()) return {Instance{}};
  std::vector<Instance> out;
  for (const Link& l : it->second)
    for (const Instance& p : instances(l.parent, depth + 1)) {
      out.push_back({p.m * l.m, p.path.empty() ? l.name : p.path + "/" + l.name});
      if (out.size() > kMaxInstances && e) fail(*e, fmt::format("is placed more than {} times", kMaxInstances));
    }
  return out;
}

std::string StepReader::product_name(long rep) {
  const auto it = product_of_group_.find(group(rep));
  if (it == product_of_group_.end()) return {};
  const StepEntity* p = f_.find(it->second);
  if (!p || !p->damage.empty()) return {};
  const StepRecord* r = p->record("PRODUCT");
  if (!r || r->params.size() < 2) return {};
  const std::string& name = r->params[1].kind == Kind::String ? r->params[1].text : std::string();
  if (!name.empty()) return name;
  return r->params[0].kind == Kind::String ? r->params[0].text : std::string();
}

StepReader::UnpairedEdges StepReader::unpaired_edges(const std::vector<FaceJob>& jobs) const {
  std::unordered_map<int, std::pair<int, int>> uses;  // edge index -> (oriented uses, first face id)
  for (const FaceJob& job : jobs)
    for (const Loop& loop : job.loops)
      for (const int edge : loop.uses) ++uses.try_emplace(edge, 0, job.f.face_id).first->second.first;
  UnpairedEdges out;
  std::unordered_map<int, long> entity_of;
  for (const auto& [ec, index] : edge_index_) entity_of.emplace(index, ec);
  for (const auto& [index, use] : uses) {
    if (use.first != 1) continue;
    const long ec = entity_of.count(index) ? entity_of.at(index) : -1;
    if (out.count++ == 0 || ec < out.edge) out.edge = ec, out.face = use.second;
  }
  return out;
}

Model StepReader::read() {
  Model model;
  model.source = f_.name;
  link_representations();
  // Solids and the representations that hold them.
  std::unordered_map<long, long> rep_of_item;
  std::unordered_map<long, long> context_of_rep;
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    for (const StepRecord& r : e.records) {
      const std::string& t = r.type;
      if (t.size() < 14 || t.compare(t.size() - 14, 14, "REPRESENTATION") != 0 || r.params.size() < 3) continue;
      if (r.params[1].kind != Kind::List) continue;
      for (const StepValue& item : r.params[1].items)
        if (item.kind == Kind::Ref) rep_of_item.emplace(item.ref, id);
      if (r.params[2].kind == Kind::Ref) context_of_rep[id] = r.params[2].ref;
      if (e.damage.empty()) visited_.insert(id);
    }
  }
  int edge_base = 0;
  long long placed_points = 0;
  double model_scale = 0.0;
  std::unordered_map<std::string, int> name_count;
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    if (!is(e, "MANIFOLD_SOLID_BREP") && !is(e, "BREP_WITH_VOIDS") && !is(e, "SHELL_BASED_SURFACE_MODEL")) continue;
    intact(e);
    visited_.insert(id);
    const auto rep = rep_of_item.find(id);
    if (rep != rep_of_item.end()) entity(rep->second, e);  // its units and placements
    length_scale_ = 1.0;
    angle_scale_ = 1.0;
    if (rep != rep_of_item.end())
      if (auto c = context_of_rep.find(rep->second); c != context_of_rep.end()) read_units(c->second, e);
    if (model_scale == 0.0) model_scale = length_scale_;
    edges_.clear();
    edge_index_.clear();
    std::vector<FaceJob> jobs = solid(e);
    if (rep != rep_of_item.end() && is(f_.entities.at(rep->second), "CONSTRUCTIVE_GEOMETRY_REPRESENTATION")) {
      // Supplemental geometry (reference planes, axes, construction surfaces: ISO 10303-242's
      // constructive geometry, as CATIA and NX write it beside the part): not the part's shape,
      // which OpenCASCADE does not transfer either. Said, not read.
      warnings_.push_back(fmt::format("#{} ({} face(s)): supplemental geometry of #{} (CONSTRUCTIVE_GEOMETRY_"
                                      "REPRESENTATION), not part of the shape, not read",
                                      id, jobs.size(), rep->second));
      model.skipped_types["supplemental geometry (CONSTRUCTIVE_GEOMETRY_REPRESENTATION) faces"] +=
          static_cast<int>(jobs.size());
      continue;
    }
    // A solid whose shell the file states closed but whose faces leave an edge with one face
    // (a face missing from the shell, a loop that skips an edge) bounds no inside: read as an
    // open shell, said once.
    bool closed = is(e, "MANIFOLD_SOLID_BREP") || is(e, "BREP_WITH_VOIDS");
    std::string not_closed;
    if (closed)
      if (const auto open = unpaired_edges(jobs); open.count > 0) {
        closed = false;
        not_closed = fmt::format("{} of its edges bound one face only (edge #{} of face #{})", open.count, open.edge,
                                 open.face);
        warnings_.push_back(
            fmt::format("#{}: the file states a closed solid, but {}: read as an open shell, with no inside", id,
                        not_closed));
      }
    const std::vector<TrimmedSurface> faces = build_faces(jobs);
    const double to_model = length_scale_ / model_scale;
    std::string name = rep != rep_of_item.end() ? product_name(rep->second) : std::string();
    if (name.empty() && !e.records.front().params.empty() && e.records.front().params[0].kind == Kind::String)
      name = e.records.front().params[0].text;
    if (name.empty()) name = fmt::format("{} #{}", is(e, "SHELL_BASED_SURFACE_MODEL") ? "surface model" : "solid", id);
    const std::vector<Instance> placed =
        rep != rep_of_item.end() ? instances(rep->second, 0) : std::vector<Instance>{{}};
    const int edges = static_cast<int>(edge_index_.size());
    // Placed copies count against the IGES reader's budget of control points (kMaxPointsBase plus
    // one per byte): an assembly naming a part at every level twice would otherwise grow without
    // bound.
    long long points = 0;
    for (const TrimmedSurface& f : faces) points += static_cast<long long>(f.surface.points.size());
    placed_points += points * static_cast<long long>(placed.size());
    if (placed_points > kMaxPointsBase + static_cast<long long>(f_.bytes))
      fail(e, fmt::format("its {} placements would create more than {} control points in all", placed.size(),
                          kMaxPointsBase + static_cast<long long>(f_.bytes)));
    for (size_t k = 0; k < placed.size(); ++k) {
      Body body;
      const int n = name_count[name]++;
      body.name = n == 0 ? name : fmt::format("{} #{}", name, n + 1);
      body.instance = placed[k].path;
      body.closed = closed;
      body.not_closed = not_closed;
      body.lose_faces(jobs.size() - faces.size());
      glm::dmat4 m = placed[k].m;
      if (to_model != 1.0) m = glm::scale(glm::dmat4(1.0), glm::dvec3(to_model)) * m;
      for (const TrimmedSurface& f : faces) {
        TrimmedSurface g = m == glm::dmat4(1.0) ? f : transformed(f, m);
        g.edge_gap = f.edge_gap * to_model;  // placements are rigid: only the unit scales it
        for (TrimLoop& l : g.loops)
          for (Curve2& c : l.curves) c.edge += edge_base;
        body.faces.push_back(std::move(g));
      }
      edge_base += edges;
      model.bodies.push_back(std::move(body));
    }
  }
  // Faces outside any shell (and shells outside any solid): one body of loose faces, as the IGES
  // reader keeps faces outside shells.
  Body loose{"faces", {}, glm::dmat4(1.0), {}};
  edges_.clear();
  edge_index_.clear();
  std::vector<FaceJob> jobs;
  for (long id : f_.order) {
    if (visited_.count(id)) continue;
    const StepEntity& e = f_.entities.at(id);
    if (is(e, "CLOSED_SHELL") || is(e, "OPEN_SHELL")) shell_faces(id, e, false, jobs);
  }
  for (long id : f_.order) {
    if (visited_.count(id)) continue;
    const StepEntity& e = f_.entities.at(id);
    if (is(e, "ADVANCED_FACE") || is(e, "FACE_SURFACE")) jobs.push_back(face_job(id, e));
  }
  loose.faces = build_faces(jobs);
  for (TrimmedSurface& f : loose.faces)
    for (TrimLoop& l : f.loops)
      for (Curve2& c : l.curves) c.edge += edge_base;
  if (!loose.faces.empty()) model.bodies.push_back(std::move(loose));
  model.unit_scale_to_mm = model_scale == 0.0 ? 1.0 : model_scale;
  model.resolution = resolution_;
  // Faces as placed: a solid an assembly places twice counts its faces twice, as the model holds them.
  model.faces_in_file = int(dropped_.size());
  for (const Body& b : model.bodies) model.faces_in_file += int(b.faces.size());
  model.dropped_faces = dropped_;
  // Loops finished once the model size is known (as the IGES reader does).
  std::vector<TrimmedSurface*> all;  // placements are in the geometry: no body transform
  for (Body& b : model.bodies)
    for (TrimmedSurface& f : b.faces) all.push_back(&f);
  std::vector<Box> boxes(all.size());  // model_size, the faces sampled on every core
  parallel_for(all.size(), 0, [&](size_t k, int) { boxes[k] = sampled_box(all[k]->surface); });
  Box box = boxes.empty() ? Box{} : boxes.front();
  for (const Box& b : boxes) box.min = glm::min(box.min, b.min), box.max = glm::max(box.max, b.max);
  double size = box.diagonal();
  if (!validate_model_size(size).empty()) size = 0.0;
  std::vector<IgesReadLog> logs(all.size());
  parallel_for(all.size(), 0, [&](size_t k, int) { finish_trim_loops(*all[k], size, logs[k]); });
  // Faces whose trim curves cannot be evaluated (finish_trim_loops said why): dropped.
  for (Body& b : model.bodies) {
    const size_t before = b.faces.size();
    std::erase_if(b.faces, [&](const TrimmedSurface& f) {
      if (trims_evaluable(f)) return false;
      model.dropped_faces.push_back({fmt::format("#{}", f.face_id), f.trim_problem});  // faces_in_file holds it
      return true;
    });
    b.lose_faces(before - b.faces.size());
  }
  // An edge the loops of two faces both skip, bridged on each: one edge (trim_surface_gaps.h).
  pair_added_edges(model.bodies, kTrimGap3d * size);
  for (const IgesReadLog& l : logs) {
    log_.reoriented_loops += l.reoriented_loops;
    log_.outer_loops_fixed += l.outer_loops_fixed;
    log_.loops_wrapped += l.loops_wrapped;
    log_.reordered_loops += l.reordered_loops;
    log_.domain_loops_added += l.domain_loops_added;
    log_.gaps_closed += l.gaps_closed;
    log_.trim_problems.insert(log_.trim_problems.end(), l.trim_problems.begin(), l.trim_problems.end());
  }
  // Geometry and topology the reader did not reach.
  static const char* kinds[] = {"SURFACE", "CURVE", "FACE", "SHELL",  "BREP",    "SOLID",
                                "EDGE",    "LOOP",  "LINE", "CIRCLE", "ELLIPSE", "VERTEX"};
  for (long id : f_.order) {
    if (visited_.count(id)) continue;
    const StepEntity& e = f_.entities.at(id);
    const std::string t = e.type_name();
    if (t == "CARTESIAN_POINT" || t == "DIRECTION" || t == "VECTOR" || t == "AXIS2_PLACEMENT_3D") continue;
    if (t.find("UNIT") != std::string::npos) continue;  // SOLID_ANGLE_UNIT and the like: not geometry
    for (const char* k : kinds)
      if (t.find(k) != std::string::npos && t.find("REPRESENTATION") == std::string::npos &&
          t.find("STYLE") == std::string::npos && t.find("PRESENTATION") == std::string::npos) {
        ++model.skipped_types[t];
        break;
      }
  }
  model.read_warnings.insert(model.read_warnings.end(), warnings_.begin(), warnings_.end());
  // Damaged records the geometry never reached (a reached one failed the read).
  for (long id : f_.order) {
    const StepEntity& e = f_.entities.at(id);
    if (!e.damage.empty() && !visited_.count(id))
      model.read_warnings.push_back(fmt::format("line {}: #{} ({}): {}; the record is not used by the geometry", e.line,
                                                id, e.type_name(), e.damage));
  }
  return model;
}

}  // namespace step_detail

using step_detail::StepReader;

Model read_step_text(const std::string& text, const std::string& name, IgesReadLog* log) {
  IgesReadLog local;
  IgesReadLog& lg = log ? *log : local;
  const StepFile file = parse_step_file(text, name);
  StepReader reader(file, lg);
  return reader.read();
}

Model read_step(const std::filesystem::path& path, IgesReadLog* log) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw ReadError(path.string(), "", "is a directory, not a STEP file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ReadError(path.string(), "", "cannot open file");
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw ReadError(path.string(), "", "read error");
  return read_step_text(buf.str(), path.string(), log);
}

}  // namespace nurbs::io
