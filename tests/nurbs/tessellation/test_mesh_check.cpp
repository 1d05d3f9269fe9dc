// The tools around the tessellation: closest points on triangles (the BVH against brute force), the
// measured deviation of a mesh from faces (it must see a moved vertex and a missing triangle), edge
// counts after welding, and the mesh writers' file layouts.
#include <doctest/doctest.h>

#include <glm/geometric.hpp>
#include <map>
#include <random>
#include <sstream>

#include "models/exact_shapes.h"
#include "models/paper_surfaces.h"
#include "nurbs/io/mesh_reader.h"
#include "nurbs/io/mesh_writer.h"
#include "nurbs/tessellation/mesh_check.h"
#include "nurbs/tessellation/mesh_parameters.h"
#include "nurbs/tessellation/mesh_topology.h"
#include "nurbs/tessellation/tessellate.h"
#include "nurbs/tessellation/triangle_bvh.h"

namespace {

/// The unit square z = 0 as a bilinear face, u = x, v = y.
nurbs::TrimmedSurface unit_square() {
  nurbs::TrimmedSurface f;
  f.surface = models::bilinear_square(1.0);
  return f;
}

/// The square as two triangles, counter-clockwise seen from +z.
nurbs::TriangleMesh square_mesh() {
  nurbs::TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

}  // namespace

TEST_CASE("mesh check: the BVH's closest point equals a brute-force search, degenerate triangles included") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> x(-1.0, 1.0);
  std::vector<std::array<glm::dvec3, 3>> tris;
  for (int k = 0; k < 400; ++k) {
    const glm::dvec3 a(x(rng), x(rng), x(rng));
    const glm::dvec3 b = k % 7 == 0 ? a : a + 0.2 * glm::dvec3(x(rng), x(rng), x(rng));  // some points
    const glm::dvec3 c = k % 5 == 0 ? b : a + 0.2 * glm::dvec3(x(rng), x(rng), x(rng));  // some segments
    tris.push_back({a, b, c});
  }
  const nurbs::tess::TriangleBvh bvh(tris);
  for (int q = 0; q < 300; ++q) {
    const glm::dvec3 p(1.5 * x(rng), 1.5 * x(rng), 1.5 * x(rng));
    double best = 1e300;
    for (const auto& t : tris)
      best = std::min(best, glm::length(nurbs::tess::closest_point_on_triangle(p, t[0], t[1], t[2]) - p));
    const auto hit = bvh.closest(p);
    CHECK(hit.distance == doctest::Approx(best).epsilon(1e-14));
    CHECK(glm::length(hit.point - p) == doctest::Approx(hit.distance).epsilon(1e-14));
    // any_within: a triangle within the radius exactly when the closest one is.
    CHECK(bvh.any_within(p, best * (1 + 1e-12)));
    CHECK(!bvh.any_within(p, best * (1 - 1e-9)));
    // for_each_near: every triangle nearer than the radius is visited, and none twice.
    const double radius = 2 * best + 0.05;
    std::vector<int> seen(tris.size(), 0);
    bvh.for_each_near(p, radius, [&](int t) { ++seen[size_t(t)]; });
    int missed = 0, twice = 0;
    for (size_t t = 0; t < tris.size(); ++t) {
      const double d = glm::length(nurbs::tess::closest_point_on_triangle(p, tris[t][0], tris[t][1], tris[t][2]) - p);
      missed += seen[t] == 0 && d < radius;
      twice += seen[t] > 1;
    }
    CHECK(missed == 0);
    CHECK(twice == 0);
  }
  // A point above a triangle's interior projects onto its plane; beside it, onto an edge.
  const glm::dvec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK(glm::length(nurbs::tess::closest_point_on_triangle({0.2, 0.2, 3}, a, b, c) - glm::dvec3(0.2, 0.2, 0)) < 1e-15);
  CHECK(glm::length(nurbs::tess::closest_point_on_triangle({0.5, -1, 0}, a, b, c) - glm::dvec3(0.5, 0, 0)) < 1e-15);
}

TEST_CASE("mesh check: a corner welded to another face's vertex does not lend its (u, v) to the triangle") {
  // Face 0: the unit square trimmed to [0.4, 0.6]^2, meshed exactly by two triangles, whose corners
  // 0, 1 and 2 are vertices of face 1 (as close_t_junctions welds coinciding vertices) carrying face
  // 1's (u, v). At 2 x 2 grid samples no sample of face 0 is material: the interior samples of the
  // first triangle are found on their face only by a search of its surface (without: up to 0.1,
  // the distance to the trim).
  nurbs::TrimmedSurface face = unit_square();
  nurbs::TrimLoop loop;
  loop.outer = true;
  nurbs::Curve2 c;
  c.degree = 1;
  c.points = {{0.4, 0.4}, {0.6, 0.4}, {0.6, 0.6}, {0.4, 0.6}, {0.4, 0.4}};
  c.knots = {0, 0, 1, 2, 3, 4, 4};
  loop.curves.push_back(c);
  face.loops.push_back(loop);
  nurbs::TrimmedSurface other = unit_square();  // face 1, 5 above
  for (glm::dvec3& q : other.surface.points) q.z += 5.0;
  const std::vector<nurbs::TrimmedSurface> faces{face, other};
  nurbs::TriangleMesh m;
  m.positions = {{0.4, 0.4, 0}, {0.6, 0.4, 0}, {0.6, 0.6, 0}, {0.4, 0.6, 0}};
  m.uv = {{5.0, 5.0}, {6.0, 5.0}, {6.0, 6.0}, {0.4, 0.6}};
  m.vertex_face = {1, 1, 1, 0};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.triangle_face = {0, 0};
  const nurbs::tess::Deviation d = nurbs::tess::measure_deviation(faces, m, {2, 0.0, 1});
  CHECK(d.mesh_to_surface < 1e-12);
}

TEST_CASE("mesh check: deviation of an exact mesh is 0; a moved vertex and a missing triangle show") {
  const std::vector<nurbs::TrimmedSurface> faces{unit_square()};
  nurbs::TriangleMesh m = square_mesh();
  const nurbs::tess::Deviation exact = nurbs::tess::measure_deviation(faces, m, {16, 0.0, 1});
  CHECK(exact.max() < 1e-12);  // the mesh lies in the face: rounding only
  CHECK(exact.surface_samples >= 16 * 16);

  // Vertex 2 lifted by 0.01: the vertex itself is 0.01 from the face (mesh to surface), and the face
  // point under it is at most 0.01 from the tilted triangles (surface to mesh, less by the tilt).
  m.positions[2].z = 0.01;
  const nurbs::tess::Deviation moved = nurbs::tess::measure_deviation(faces, m, {16, 0.0, 1});
  CHECK(moved.mesh_to_surface == doctest::Approx(0.01).epsilon(1e-9));
  CHECK(moved.surface_to_mesh > 0.009);
  CHECK(moved.surface_to_mesh <= 0.01);

  // Without the second triangle, the corner (0, 1) is sqrt(1/2) from the remaining one.
  nurbs::TriangleMesh half = square_mesh();
  half.triangles.pop_back();
  const nurbs::tess::Deviation missing = nurbs::tess::measure_deviation(faces, half, {16, 0.0, 1});
  CHECK(missing.surface_to_mesh == doctest::Approx(std::sqrt(0.5)).epsilon(1e-9));
  CHECK(missing.mesh_to_surface < 1e-12);
  CHECK(missing.worst_face == 0);
}

TEST_CASE("mesh check: a triangle beyond every sample's reach gets no face and is still measured") {
  // 1e155 squared overflows the BVH's search radius (1e300): no nearest sample. The triangle keeps its
  // corners with face -1 (it had read the sample list at index -1), the other one gets face 0.
  const std::vector<nurbs::TrimmedSurface> faces{unit_square()};
  nurbs::TriangleMesh m = square_mesh();
  m.positions.push_back({1e155, 0, 0});
  m.triangles.push_back({0, 1, 4});
  const nurbs::TriangleMesh with = nurbs::tess::with_face_parameters(faces, m, 8, 1);
  REQUIRE(with.triangle_face.size() == 3);
  CHECK(with.triangle_face[0] == 0);
  CHECK(with.triangle_face[2] == -1);
  CHECK(with.vertex_face[8] == -1);
  CHECK(with.positions[8] == glm::dvec3(1e155, 0, 0));
  const nurbs::tess::Deviation d = nurbs::tess::measure_deviation(faces, with, {8, 0.0, 1});
  CHECK(d.mesh_to_surface > 1e154);  // the far corner's distance, not a crash
}

TEST_CASE("mesh check: per-face deviations; a triangle across a concave trim shows on its face alone") {
  // Face 0: the square [0, 10]^2 trimmed to a U (a notch x in [3, 7], y > 4 cut away), as a planar
  // face with one outer loop of degree-1 curves; face 1: an untrimmed square beside it.
  nurbs::TrimmedSurface u_face, other;
  u_face.surface = models::bilinear_square(10.0);
  const glm::dvec2 corners[] = {{0, 0}, {10, 0}, {10, 10}, {7, 10}, {7, 4}, {3, 4}, {3, 10}, {0, 10}};
  nurbs::TrimLoop loop;
  loop.outer = true;
  for (size_t k = 0; k < 8; ++k) loop.curves.push_back(models::trim_line(corners[k], corners[(k + 1) % 8]));
  u_face.loops.push_back(loop);
  other.surface = models::bilinear_square(10.0);
  for (auto& p : other.surface.points) p.x += 20.0;
  const std::vector<nurbs::TrimmedSurface> faces{u_face, other};
  nurbs::tess::TessellateOptions o;
  o.eps = 1e-2;
  nurbs::tess::TessellateResult r = nurbs::tess::tessellate(faces, o);
  REQUIRE(r.failures.empty());
  const auto good = nurbs::tess::triangles_outside_trim(faces, r.mesh, o.eps);
  REQUIRE(good.size() == 2);
  CHECK(good[0].triangles == 0);
  CHECK(good[1].triangles == 0);
  const nurbs::tess::Deviation fine = nurbs::tess::measure_deviation(faces, r.mesh, {16, 0.0, 1});
  REQUIRE(fine.face_mesh_to_surface.size() == 2);
  CHECK(fine.face_mesh_to_surface[0] <= o.eps);
  CHECK(fine.face_surface_to_mesh[1] <= o.eps);
  // A triangle of face 0 across the notch, its corners on the loop at (3, 10), (7, 10), (5, 4):
  // its centroid (5, 8) lies 2 outside the material (the notch's sides are 2 away).
  nurbs::TriangleMesh bad = r.mesh;
  const int v = int(bad.positions.size());
  for (const glm::dvec2 uv : {glm::dvec2(3, 10), glm::dvec2(7, 10), glm::dvec2(5, 4)}) {
    bad.positions.emplace_back(uv.x, uv.y, 0.0);
    bad.uv.push_back(uv);
    bad.vertex_face.push_back(0);
    if (!bad.normals.empty()) bad.normals.emplace_back(0.0, 0.0, 1.0);
  }
  bad.triangles.emplace_back(v, v + 1, v + 2);
  bad.triangle_face.push_back(0);
  const auto found = nurbs::tess::triangles_outside_trim(faces, bad, o.eps);
  CHECK(found[0].triangles == 1);
  CHECK(found[0].distance == doctest::Approx(2.0).epsilon(1e-3));
  CHECK(found[1].triangles == 0);
  const nurbs::tess::Deviation measured = nurbs::tess::measure_deviation(faces, bad, {16, 0.0, 1});
  CHECK(measured.face_mesh_to_surface[0] >= 1.9);
  CHECK(measured.face_mesh_to_surface[1] <= o.eps);
  // The face alone, as the check's per-face measurement sees it.
  const nurbs::TriangleMesh alone = nurbs::tess::face_submesh(bad, 0);
  CHECK(alone.triangles.size() < bad.triangles.size());
  CHECK(nurbs::tess::measure_deviation({u_face}, alone, {16, 0.0, 1}).mesh_to_surface >= 1.9);
}

TEST_CASE("mesh check: triangles off their surface are found by their face, a good mesh passes") {
  // A sphere and a torus, tessellated within eps: no sample of any triangle off its surface. Then one
  // vertex of the torus lifted 5 eps along its normal: the triangles around it, on face 1 alone.
  std::vector<nurbs::TrimmedSurface> faces(2);
  faces[0].surface = models::rational_sphere(3.0);
  faces[1].surface = models::rational_torus(8.0, 2.0);
  nurbs::tess::TessellateOptions o;
  o.eps = 0.1;
  const nurbs::tess::TessellateResult r = nurbs::tess::tessellate(faces, o);
  REQUIRE(r.failures.empty());
  const auto good = nurbs::tess::triangles_off_surface(faces, r.mesh, o.eps);
  REQUIRE(good.size() == 2);
  CHECK(good[0].triangles == 0);
  CHECK(good[1].triangles == 0);
  CHECK(good[1].distance <= o.eps);
  CHECK(good[1].distance > 0.0);
  nurbs::TriangleMesh bad = r.mesh;
  size_t v = 0;
  while (v < bad.positions.size() && bad.vertex_face[v] != 1) ++v;
  REQUIRE(v < bad.positions.size());
  REQUIRE(!bad.normals.empty());
  bad.positions[v] += 5.0 * o.eps * glm::normalize(bad.normals[v]);
  const auto found = nurbs::tess::triangles_off_surface(faces, bad, o.eps);
  CHECK(found[0].triangles == 0);
  CHECK(found[1].triangles >= 1);
  CHECK(found[1].distance > o.eps);
  CHECK(found[1].distance < 5.0 * o.eps);  // samples at the centroids and midpoints, not the vertex
}

TEST_CASE("mesh check: open edges after welding") {
  nurbs::TriangleMesh square = square_mesh();
  auto e = nurbs::tess::count_edges(square, 1e-9);
  CHECK(e.edges == 5);
  CHECK(e.open == 4);
  // A tetrahedron is closed; its four faces as separate triangles (12 vertices) weld into it.
  nurbs::TriangleMesh tet;
  const glm::dvec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  for (const auto& t : f) {
    const int base = int(tet.positions.size());
    for (int c = 0; c < 3; ++c) tet.positions.push_back(p[t[c]] + glm::dvec3(1e-12 * c));  // below the weld
    tet.triangles.push_back({base, base + 1, base + 2});
  }
  e = nurbs::tess::count_edges(tet, 1e-9);
  CHECK(e.welded_vertices == 4);
  CHECK(e.edges == 6);
  CHECK(e.open == 0);
  tet.triangles.pop_back();
  CHECK(nurbs::tess::count_edges(tet, 1e-9).open == 3);
  // By face: without faces all three under -1; with them, one on each face beside the missing one.
  CHECK(nurbs::tess::count_edges(tet, 1e-9).open_by_face == std::map<int, long long>{{-1, 3}});
  tet.triangle_face = {10, 11, 12};
  CHECK(nurbs::tess::count_edges(tet, 1e-9).open_by_face == std::map<int, long long>{{10, 1}, {11, 1}, {12, 1}});
  tet.triangle_face.clear();
  // A weld tolerance below the offsets keeps the faces apart: every edge is open.
  CHECK(nurbs::tess::count_edges(tet, 1e-13).open == 9);
  // As indexed (as a file holds it) the separate triangles are open; welded into one mesh, closed.
  tet.triangles.push_back({9, 10, 11});
  tet.normals.assign(12, glm::dvec3(0.0, 0.0, 1.0));
  tet.normals[0] = glm::dvec3(1.0, 0.0, 0.0);  // vertex p[0] of the first triangle: the group's normal is the mean
  CHECK(nurbs::tess::count_edges_as_indexed(tet).open == 12);
  long long collapsed = -1;
  const nurbs::TriangleMesh welded = nurbs::tess::weld_mesh(tet, 1e-9, &collapsed);
  CHECK(welded.positions.size() == 4);
  CHECK(welded.triangles.size() == 4);
  CHECK(collapsed == 0);
  const nurbs::tess::EdgeCounts w = nurbs::tess::count_edges_as_indexed(welded);
  CHECK(w.edges == 6);
  CHECK(w.open == 0);
  CHECK(glm::length(welded.normals[0] - glm::normalize(glm::dvec3(1.0, 0.0, 2.0))) < 1e-12);  // 1 of 3 was +x
  // A weld that merges two corners of a triangle drops it.
  nurbs::TriangleMesh thin;
  thin.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1e-10, 0}, {0, 1, 0}};
  thin.triangles = {{0, 1, 2}, {0, 1, 3}};
  const nurbs::TriangleMesh fixed = nurbs::tess::weld_mesh(thin, 1e-9, &collapsed);
  CHECK(collapsed == 1);
  CHECK(fixed.triangles.size() == 1);
}

TEST_CASE("mesh check: mesh writers (OBJ, PLY, STL layouts, format from the extension)") {
  nurbs::TriangleMesh m = square_mesh();
  m.normals.assign(4, glm::dvec3(0, 0, 1));
  m.triangle_face = {0, 0};
  std::ostringstream stl, ply, obj;
  nurbs::io::write_mesh(stl, m, nurbs::io::MeshFormat::Stl);
  CHECK(stl.str().size() == 84 + 50 * 2);  // header, count, 50 bytes per facet
  nurbs::io::write_mesh(ply, m, nurbs::io::MeshFormat::Ply);
  const std::string header = ply.str().substr(0, ply.str().find("end_header\n") + 11);
  CHECK(header.find("element vertex 4\n") != std::string::npos);
  CHECK(header.find("element face 2\n") != std::string::npos);
  CHECK(header.find("property float nx\n") != std::string::npos);
  CHECK(header.find("property double x\nproperty double y\nproperty double z\n") != std::string::npos);
  // Vertices: 4 x (3 doubles + 3 floats); faces: 2 x (1 + 3 x 4 + face_id 4) bytes.
  CHECK(ply.str().size() == header.size() + 4 * (3 * 8 + 3 * 4) + 2 * (1 + 12 + 4));
  CHECK(header.find("comment nurbsgl tessellation\n") != std::string::npos);
  // A per-vertex scalar (the thickness samples' values) is a float property of its name.
  m.values = {1.0, 2.0, 3.0, -1.0};
  m.values_name = "thickness";
  std::ostringstream with_values;
  nurbs::io::write_mesh(with_values, m, nurbs::io::MeshFormat::Ply);
  const std::string header2 = with_values.str().substr(0, with_values.str().find("end_header\n") + 11);
  CHECK(header2.find("property float nz\nproperty float thickness\nelement face 2\n") != std::string::npos);
  CHECK(header2.find("comment nurbsgl thickness samples\n") != std::string::npos);
  CHECK(with_values.str().size() == header2.size() + 4 * (3 * 8 + 4 * 4) + 2 * (1 + 12 + 4));
  m.values.clear();
  {
    // A needle: corner 3 a billionth from corner 1, distinct in double, one point in float. The
    // PLY keeps its area (positions in double); the STL leaves the facet out.
    nurbs::TriangleMesh needle;
    needle.positions = {{100, 100, 100}, {101, 100, 100}, {100, 100 + 1e-9, 100}, {100, 101, 100}};
    needle.triangles = {{0, 1, 2}, {0, 1, 3}};
    std::ostringstream p2, s2;
    nurbs::io::write_mesh(p2, needle, nurbs::io::MeshFormat::Ply);
    std::istringstream back(p2.str());
    const nurbs::TriangleMesh read = nurbs::io::read_mesh(back, nurbs::io::MeshFormat::Ply, "needle.ply");
    REQUIRE(read.positions.size() == 4);
    CHECK(read.positions[2] != read.positions[0]);
    CHECK(read.positions[2].y == 100 + 1e-9);
    nurbs::io::write_mesh(s2, needle, nurbs::io::MeshFormat::Stl);
    CHECK(s2.str().size() == 84 + 50 * 1);
  }
  nurbs::io::write_mesh(obj, m, nurbs::io::MeshFormat::Obj);
  CHECK(obj.str().find("f 1//1 2//2 3//3\n") != std::string::npos);
  CHECK(obj.str().find("g face_0\n") != std::string::npos);
  CHECK(nurbs::io::mesh_format_of("a/B.PLY") == nurbs::io::MeshFormat::Ply);
  CHECK_THROWS_WITH_AS((void)nurbs::io::mesh_format_of("x.txt"),
                       "x.txt: unknown mesh format '.txt' (use .obj, .ply or .stl)", std::invalid_argument);
}
