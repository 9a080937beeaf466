// radar_ndt's compiled module (_radar_ndt): the library's matchers, readers, front-ends,
// odometries, runs and metrics on numpy arrays. The package python/radar_ndt/ re-exports it.
// Errors: std::invalid_argument (a setting out of range, validate()) is ValueError; a run's keyword
// that names no setting, or of the wrong type, is TypeError (SettingError); IoError (a file that
// cannot be read, naming it) is radar_ndt.IoError, an OSError with `filename` and `line`.

#include "bindings.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/pipeline/run_settings.h"

namespace py = pybind11;

PYBIND11_MODULE(_radar_ndt, m) {
  using namespace radar_ndt::python;
  m.doc() = "RadarNDT: radar odometry with the weighted probabilistic NDT (C++ library bindings).";

  static py::handle io_error = PyErr_NewExceptionWithDoc(
      "radar_ndt.IoError",
      "A file that cannot be read or written: the message names the file and the problem; `filename` and "
      "`line` (1-based, 0 when not tied to a line) say where.",
      PyExc_OSError, nullptr);
  // OSError's own str() shows "[Errno None] None: 'file'" once `filename` is set, which hides the
  // problem: the message (it names the file and the problem) is what str() gives, and strerror too.
  py::reinterpret_borrow<py::object>(io_error).attr("__str__") = py::cpp_function(
      [](py::handle self) { return py::str(py::tuple(self.attr("args"))[0]); }, py::is_method(io_error));
  m.add_object("IoError", io_error);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const radar_ndt::IoError& e) {
      py::object err = io_error(py::str(e.what()));
      err.attr("strerror") = e.what();
      err.attr("filename") = e.file();
      err.attr("line") = e.line();
      PyErr_SetObject(io_error.ptr(), err.ptr());
    } catch (const radar_ndt::SettingError& e) {
      // A keyword that names no setting of the run, or a value of the wrong type, is a TypeError
      // (as an unknown keyword argument is); a value out of range a ValueError.
      PyErr_SetString(e.why() == radar_ndt::SettingError::Why::Value ? PyExc_ValueError : PyExc_TypeError, e.what());
    }
  });

  py::tuple fields(kPointFieldCount);
  for (int i = 0; i < kPointFieldCount; ++i) fields[i] = kPointFields[i];
  m.attr("POINT_FIELDS") = fields;

  bindOptions(m);
  bindRegistration(m);
  bindIo(m);
  bindFrontEnd(m);
  bindOdometry(m);
  bindRuns(m);
  bindEvaluation(m);
}
