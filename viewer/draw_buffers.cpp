#include "viewer/draw_buffers.h"

#include <numeric>

#include "gpgpu/gl_api.h"
#include "viewer/gl_extra.h"

namespace viewer {

namespace gl = gpgpu::gl;

VertexArray::VertexArray() = default;

VertexArray::~VertexArray() {
  if (vao_ == 0) return;
  gl::DeleteBuffers(1, &vbo_);
  gl::DeleteBuffers(1, &ebo_);
  gl::DeleteVertexArrays(1, &vao_);
}

void VertexArray::create() {
  if (vao_ != 0) return;
  gl::CreateVertexArrays(1, &vao_);
  gl::CreateBuffers(1, &vbo_);
  gl::CreateBuffers(1, &ebo_);
}

void VertexArray::set_vertices(const std::vector<float>& data, const std::vector<int>& sizes) {
  create();
  const int stride = std::accumulate(sizes.begin(), sizes.end(), 0);
  gl::NamedBufferData(vbo_, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), GL_STATIC_DRAW);
  gl::VertexArrayVertexBuffer(vao_, 0, vbo_, 0, static_cast<GLsizei>(stride * sizeof(float)));
  int offset = 0;
  for (size_t i = 0; i < sizes.size(); ++i) {
    const auto loc = static_cast<GLuint>(i);
    gl::EnableVertexArrayAttrib(vao_, loc);
    gl::VertexArrayAttribFormat(vao_, loc, sizes[i], GL_FLOAT, GL_FALSE, static_cast<GLuint>(offset * sizeof(float)));
    gl::VertexArrayAttribBinding(vao_, loc, 0);
    offset += sizes[i];
  }
  vertices_ = stride == 0 ? 0 : static_cast<long long>(data.size()) / stride;
  gl::check_error("viewer vertex upload");
}

void VertexArray::set_indices(const std::vector<unsigned>& indices) {
  create();
  gl::NamedBufferData(ebo_, static_cast<GLsizeiptr>(indices.size() * sizeof(unsigned)), indices.data(), GL_STATIC_DRAW);
  glx::VertexArrayElementBuffer(vao_, ebo_);
  indices_ = static_cast<long long>(indices.size());
  gl::check_error("viewer index upload");
}

void MeshBuffers::upload(const nurbs::TriangleMesh& mesh, const std::vector<float>& scalar) {
  std::vector<float> v;
  v.reserve(mesh.positions.size() * 8);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::dvec3 p = mesh.positions[i];
    const glm::dvec3 n = i < mesh.normals.size() ? mesh.normals[i] : glm::dvec3(0.0, 0.0, 1.0);
    const float face = i < mesh.vertex_face.size() ? static_cast<float>(mesh.vertex_face[i]) : -1.0f;
    const float s = i < scalar.size() ? scalar[i] : -1.0f;
    v.insert(v.end(), {float(p.x), float(p.y), float(p.z), float(n.x), float(n.y), float(n.z), face, s});
  }
  std::vector<unsigned> idx;
  idx.reserve(mesh.triangles.size() * 3);
  for (const glm::ivec3& t : mesh.triangles) idx.insert(idx.end(), {unsigned(t.x), unsigned(t.y), unsigned(t.z)});
  vao_.set_vertices(v, {3, 3, 1, 1});
  vao_.set_indices(idx);
}

void MeshBuffers::draw(const gpgpu::Program& program) const {
  if (vao_.indices() == 0) return;
  gl::UseProgram(program.id());
  gl::BindVertexArray(vao_.id());
  glx::DrawElements(GL_TRIANGLES, static_cast<GLsizei>(vao_.indices()), GL_UNSIGNED_INT, nullptr);
  gl::BindVertexArray(0);
  gl::UseProgram(0);
}

void LineBatch::clear() {
  lines_.clear();
  triangles_.clear();
  dirty_ = true;
}

void LineBatch::line(const glm::dvec3& a, const glm::dvec3& b, const glm::vec3& c) {
  lines_.insert(lines_.end(), {float(a.x), float(a.y), float(a.z), c.x, c.y, c.z});
  lines_.insert(lines_.end(), {float(b.x), float(b.y), float(b.z), c.x, c.y, c.z});
  dirty_ = true;
}

void LineBatch::triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& d, const glm::vec3& c) {
  for (const glm::dvec3& p : {a, b, d})
    triangles_.insert(triangles_.end(), {float(p.x), float(p.y), float(p.z), c.x, c.y, c.z});
  dirty_ = true;
}

void LineBatch::box(const glm::dvec3& lo, const glm::dvec3& hi, const glm::vec3& color) {
  auto corner = [&](int k) { return glm::dvec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z); };
  for (int k = 0; k < 8; ++k)
    for (int bit : {1, 2, 4})
      if ((k & bit) == 0) line(corner(k), corner(k | bit), color);
}

void LineBatch::draw(const gpgpu::Program& program) {
  if (dirty_) {
    line_vao_.set_vertices(lines_, {3, 3});
    triangle_vao_.set_vertices(triangles_, {3, 3});
    dirty_ = false;
  }
  gl::UseProgram(program.id());
  if (line_vao_.vertices() > 0) {
    gl::BindVertexArray(line_vao_.id());
    gl::DrawArrays(GL_LINES, 0, static_cast<GLsizei>(line_vao_.vertices()));
  }
  if (triangle_vao_.vertices() > 0) {
    gl::BindVertexArray(triangle_vao_.id());
    gl::DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangle_vao_.vertices()));
  }
  gl::BindVertexArray(0);
  gl::UseProgram(0);
}

}  // namespace viewer
