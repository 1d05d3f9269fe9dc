// What OpenCASCADE holds valid in a file (built only with -DNURBSGL_PEER_BENCH=ON): the reference of
// experiments/trim_validity.py for which trims and shells are valid. For each file, read by OCCT's
// own readers (peer_occt_read.h), one JSON line: its faces, and each face BRepCheck_Analyzer finds
// invalid with the statuses BRepCheck reports on the face and its wires, and the centre of its box
// (model units as OCCT reads them: mm), so that a caller can match it to a face of its own.
// Usage: peer_occt_check FILE...
#include <BRepBndLib.hxx>
#include <BRepCheck.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepCheck_ListOfStatus.hxx>
#include <BRepCheck_Result.hxx>
#include <BRepCheck_Status.hxx>
#include <Bnd_Box.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <nlohmann/json.hpp>

#include <iostream>
#include <sstream>
#include <string>

#include "peer_occt_read.h"

namespace {

std::string status_names(const BRepCheck_Analyzer& check, const TopoDS_Shape& face) {
  std::string out;
  const auto add = [&](const TopoDS_Shape& s) {
    const Handle(BRepCheck_Result)& r = check.Result(s);
    if (r.IsNull()) return;
    for (BRepCheck_ListIteratorOfListOfStatus it(r->Status()); it.More(); it.Next())
      if (it.Value() != BRepCheck_NoError) {
        std::ostringstream name;
        BRepCheck::Print(it.Value(), name);
        std::string text = name.str();
        while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
        if (out.find(text) == std::string::npos) out += (out.empty() ? "" : ", ") + text;
      }
  };
  add(face);
  for (TopExp_Explorer w(face, TopAbs_WIRE); w.More(); w.Next()) add(w.Current());
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  for (int k = 1; k < argc; ++k) {
    const std::string path = argv[k];
    nlohmann::json j = {{"file", path}};
    try {
      double seconds = 0.0;
      const TopoDS_Shape shape = peer::read_shape(path, seconds);
      int index = 0;
      nlohmann::json invalid = nlohmann::json::array();
      for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next(), ++index) {
        const TopoDS_Face& face = TopoDS::Face(e.Current());
        const BRepCheck_Analyzer check(face);
        if (check.IsValid()) continue;
        Bnd_Box box;
        BRepBndLib::Add(face, box);
        double x0 = 0, y0 = 0, z0 = 0, x1 = 0, y1 = 0, z1 = 0;
        if (!box.IsVoid()) box.Get(x0, y0, z0, x1, y1, z1);
        invalid.push_back({{"face", index},
                           {"centre", {0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (z0 + z1)}},
                           {"status", status_names(check, face)}});
      }
      j["faces"] = index;
      j["invalid_faces"] = invalid;
    } catch (const std::exception& e) {
      j["error"] = e.what();
    }
    std::cout << j.dump() << std::endl;
  }
  return 0;
}
