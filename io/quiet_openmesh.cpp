#include "io/quiet_openmesh.hpp"

#include <OpenMesh/Core/System/omstream.hh>

#include <iostream>

namespace lhr {

QuietOpenMesh::QuietOpenMesh()
    : err_(omerr().is_enabled()),
      log_(omlog().is_enabled()),
      out_(omout().is_enabled()),
      cerr_(std::cerr.rdbuf(&sink_)),
      clog_(std::clog.rdbuf(&sink_)) {
  omerr().disable();
  omlog().disable();
  omout().disable();
}

QuietOpenMesh::~QuietOpenMesh() {
  std::cerr.rdbuf(cerr_);
  std::clog.rdbuf(clog_);
  if (err_) omerr().enable();
  if (log_) omlog().enable();
  if (out_) omout().enable();
}

}  // namespace lhr
