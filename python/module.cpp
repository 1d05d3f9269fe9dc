// The compiled half of the Python module nurbsgl (_nurbsgl): the library's front doors on numpy
// arrays. Each query copies its input out of Python, runs with the GIL released (GL work on the
// module's GL thread, gl_thread.h) and hands its answers back as arrays in a dict, which
// nurbsgl/__init__.py turns into result objects. Errors are the library's exceptions, translated
// to nurbsgl.ReadError (the readers), nurbsgl.RequestError (a request refused) and nurbsgl.NoGLError.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "gpgpu/context.h"
#include "nurbs/io/point_cloud.h"
#include "nurbs/io/read_error.h"
#include "nurbs/io/read_model.h"
#include "nurbs/model_ops.h"
#include "nurbs/request_error.h"
#include "python/convert.h"
#include "python/gl_thread.h"
#include "python/model_binding.h"
#include "python/queries_binding.h"

namespace py = pybind11;
using namespace nurbsgl_python;

namespace {

std::shared_ptr<ModelBinding> load(const std::string& path) {
  auto out = std::make_shared<ModelBinding>();
  {
    py::gil_scoped_release release;
    out->loaded = std::make_shared<const nurbs::LoadedModel>(nurbs::io::load_model(path));
  }
  return out;
}

py::dict model_info(const ModelBinding& m) {
  const nurbs::LoadedModel& l = *m.loaded;
  py::dict d;
  py::list bodies;
  for (const nurbs::Body& b : l.model.bodies) {
    py::dict body;
    body["name"] = b.name;
    body["instance"] = b.instance;
    body["faces"] = b.faces.size();
    body["closed"] = b.closed;
    bodies.append(body);
  }
  d["path"] = l.path.string();
  d["bodies"] = bodies;
  d["faces"] = nurbs::world_faces(l.model).size();
  d["faces_in_file"] = l.report.faces_in_file;
  d["size"] = nurbs::model_size(l.model);
  d["unit"] = nurbs::unit_name(l.model);
  d["unit_scale_to_mm"] = l.model.unit_scale_to_mm;
  py::list dropped;
  for (const nurbs::DroppedFace& f : l.report.dropped) dropped.append(f.entity + ": " + f.reason);
  d["dropped"] = dropped;
  d["changed"] = l.report.changed();
  d["changes"] = l.report.lines();
  return d;
}

py::dict read_points(const std::string& path) {
  nurbs::io::PointCloud cloud;
  {
    py::gil_scoped_release release;
    cloud = nurbs::io::read_point_cloud_file(path);
  }
  py::dict d;
  d["points"] = array3(cloud.points);
  d["normals"] = cloud.normals.empty() ? py::object(py::none()) : py::object(array3(cloud.normals));
  if (cloud.colors.empty()) {
    d["colors"] = py::none();
  } else {
    py::array_t<uint8_t> colors({py::ssize_t(cloud.colors.size()), py::ssize_t(3)});
    std::memcpy(colors.mutable_data(), cloud.colors.data(), cloud.colors.size() * 3);
    d["colors"] = colors;
  }
  d["format"] = cloud.format;
  return d;
}

}  // namespace

PYBIND11_MODULE(_nurbsgl, m) {
  m.doc() = "nurbsgl's compiled front doors; use the nurbsgl package, which wraps them.";
  py::register_exception<nurbs::io::ReadError>(m, "ReadError", PyExc_ValueError);
  py::register_exception<nurbs::RequestError>(m, "RequestError", PyExc_ValueError);
  py::register_exception<gpgpu::NoGlError>(m, "NoGLError", PyExc_RuntimeError);

  py::class_<ModelBinding, std::shared_ptr<ModelBinding>>(m, "Model")
      .def("info", &model_info, "The model's bodies, faces, size, unit and what the reader changed.")
      .def("distance", &point_distance, py::arg("points"), py::arg("tol"), py::arg("engine"), py::arg("per_point"),
           py::arg("accept_partial"), py::arg("cache"), py::arg("signed"), py::arg("strict"))
      .def("inspect", &inspect, py::arg("scan"), py::arg("within"), py::arg("max_distance"), py::arg("tol"),
           py::arg("transform"), py::arg("align"), py::arg("align_faces"), py::arg("align_sample"), py::arg("engine"),
           py::arg("accept_partial"))
      .def("tessellate", &tessellate, py::arg("eps"), py::arg("relative"), py::arg("watertight"),
           py::arg("guaranteed"), py::arg("check"), py::arg("accept_partial"))
      .def("raycast", &raycast, py::arg("origins"), py::arg("directions"), py::arg("t_min"), py::arg("engine"),
           py::arg("tol"), py::arg("mesh_tol"), py::arg("accept_partial"))
      .def("thickness", &thickness, py::arg("samples"), py::arg("engine"), py::arg("ball"), py::arg("min_wall"),
           py::arg("accept_partial"));
  m.def("load", &load, py::arg("path"), "Reads an IGES, STEP or .bpt file.");
  m.def("read_points", &read_points, py::arg("path"), "Reads a file of points: PLY, .npy or text (point_cloud.h).");
  m.def("clearance", &clearance, py::arg("a"), py::arg("b"), py::arg("motions"), py::arg("body_a"),
        py::arg("body_b"), py::arg("tol"), py::arg("engine"), py::arg("voxel_stage"), py::arg("accept_partial"));
  m.def("clash", &clash, py::arg("model"), py::arg("min_clearance"), py::arg("tol"), py::arg("engine"),
        py::arg("accept_partial"), py::arg("pairs"));
  m.def(
      "gl_info",
      [] {
        gpgpu::ContextInfo info;
        {
          py::gil_scoped_release release;
          GlThread::instance().run([&] { info = GlThread::instance().gpu().info(); });
        }
        py::dict d;
        d["backend"] = info.backend;
        d["renderer"] = info.renderer;
        d["gl_version"] = info.gl_version;
        d["max_texture_size"] = info.max_texture_size;
        d["memory_bytes"] = info.memory_bytes;
        d["software_renderer"] = gpgpu::software_renderer(info.renderer);
        d["hardware_unused"] = info.hardware_unused;
        return d;
      },
      "The GL context's backend, renderer and version (started on first use).");
}
