#pragma once
/// \file peer_occt_read.h
/// What the OpenCASCADE peers share: reading an IGES or STEP file with OCCT's own readers (no nurbsgl code,
/// so the peer stays independent) and a wall-clock timer.
#include <IGESControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <TopoDS_Shape.hxx>

#include <cctype>
#include <chrono>
#include <stdexcept>
#include <string>

namespace peer {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The file's shape read by OCCT's `Reader` (IGESControl_Reader, STEPControl_Reader), every root
/// transferred; `seconds` gets the time of reading and transfer. Throws std::runtime_error naming
/// the file when OCCT cannot read it or transfers nothing.
template <class Reader>
TopoDS_Shape read_with(const std::string& path, double& seconds) {
  const auto t0 = Clock::now();
  Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) throw std::runtime_error(path + ": OCCT cannot read it");
  reader.TransferRoots();
  TopoDS_Shape shape = reader.OneShape();
  seconds = seconds_since(t0);
  if (shape.IsNull()) throw std::runtime_error(path + ": OCCT transferred no shape");
  return shape;
}

inline TopoDS_Shape read_iges(const std::string& path, double& seconds) {
  return read_with<IGESControl_Reader>(path, seconds);
}

inline TopoDS_Shape read_step(const std::string& path, double& seconds) {
  return read_with<STEPControl_Reader>(path, seconds);
}

/// read_step for .stp / .step (any case), else read_iges.
inline TopoDS_Shape read_shape(const std::string& path, double& seconds) {
  std::string ext = path.substr(path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".stp" || ext == ".step" ? read_step(path, seconds) : read_iges(path, seconds);
}

}  // namespace peer
