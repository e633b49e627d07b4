// The extension module rove._rove; the package rove (python/rove) re-exports
// it. Each part registers its classes and functions in its own file.

#include "bindings.h"

PYBIND11_MODULE(_rove, m) {
  m.doc() = "rove: a toolkit for mobile robots (C++), from Python.";
  rove::python::bind_errors(m);
  rove::python::bind_geometry(m);
  rove::python::bind_clouds(m);
  rove::python::bind_grids(m);
  rove::python::bind_io(m);
  rove::python::bind_registration(m);
  rove::python::bind_graph(m);
  rove::python::bind_slam(m);
  rove::python::bind_filters(m);
  rove::python::bind_eval(m);
  rove::python::bind_nav(m);
  rove::python::bind_mapping(m);
  rove::python::bind_rawlog_tools(m);
  rove::python::bind_rgbd(m);
}
