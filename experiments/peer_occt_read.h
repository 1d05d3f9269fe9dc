#pragma once
/// \file peer_occt_read.h
/// What the OpenCASCADE peers share: reading an IGES file with OCCT's own reader (no nurbsgl code,
/// so the peer stays independent) and a wall-clock timer.
#include <IGESControl_Reader.hxx>
#include <TopoDS_Shape.hxx>

#include <chrono>
#include <stdexcept>
#include <string>

namespace peer {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The file's shape, every root transferred; `seconds` gets the time of reading and transfer.
/// Throws std::runtime_error naming the file when OCCT cannot read it or transfers nothing.
inline TopoDS_Shape read_iges(const std::string& path, double& seconds) {
  const auto t0 = Clock::now();
  IGESControl_Reader reader;
  if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) throw std::runtime_error(path + ": OCCT cannot read it");
  reader.TransferRoots();
  TopoDS_Shape shape = reader.OneShape();
  seconds = seconds_since(t0);
  if (shape.IsNull()) throw std::runtime_error(path + ": OCCT transferred no shape");
  return shape;
}

}  // namespace peer
