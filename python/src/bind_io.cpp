// The readers: polar scans (Oxford, RADIATE, Boreas) as numpy views, scanning sequences, nuScenes
// tables, sweeps and cycles, and trajectory files. Reading runs without the GIL.

#include <memory>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>  // paths as str or os.PathLike

#include "bindings.h"
#include "keywords.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/nuscenes_can_bus.h"
#include "radar_ndt/io/nuscenes_sequence.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/io/scanning_sequence.h"

namespace radar_ndt {
namespace python {

namespace {

using ScanPtr = std::shared_ptr<PolarScan>;

/// A view of `values` (owned by the scan `owner`) shaped `shape`, writable.
template <typename T>
py::array_t<T> view(std::vector<T>& values, const py::object& owner, std::vector<py::ssize_t> shape) {
  if (values.empty()) return py::array_t<T>(shape);
  std::vector<py::ssize_t> strides(shape.size(), static_cast<py::ssize_t>(sizeof(T)));
  for (std::size_t d = shape.size() - 1; d-- > 0;) strides[d] = strides[d + 1] * shape[d + 1];
  return py::array_t<T>(shape, strides, values.data(), owner);
}

ScanPtr readScan(const std::function<PolarScan()>& read) {
  py::gil_scoped_release release;
  return std::make_shared<PolarScan>(read());
}

void bindPolarScanRows(py::class_<PolarScan, ScanPtr>& c);

void bindPolarScanClass(py::module_& m) {
  py::class_<PolarScan, ScanPtr> c(
      m, "PolarScan",
      "One sweep of a scanning radar (radar_ndt/io/polar_scan.h). The arrays are views of the scan's "
      "own memory (writable: a change reaches the front-end); azimuth angles are in the vehicle frame "
      "(rad, counter-clockwise from x forward), times in microseconds.");
  c.def_readonly("azimuths", &PolarScan::azimuths)
      .def_readonly("bins", &PolarScan::bins)
      .def_property_readonly(
          "power",
          [](py::object self) {
            auto& s = self.cast<PolarScan&>();
            return view(s.power, self, {s.azimuths, s.bins});
          },
          "numpy.ndarray: (azimuths, bins) uint8 power, 0..255")
      .def_property_readonly(
          "angle",
          [](py::object self) {
            auto& s = self.cast<PolarScan&>();
            return view(s.angle, self, {s.azimuths});
          },
          "numpy.ndarray: (azimuths,) vehicle-frame angle of each row (rad)")
      .def_property_readonly(
          "stamp_us",
          [](py::object self) {
            auto& s = self.cast<PolarScan&>();
            return view(s.stamp_us, self, {s.azimuths});
          },
          "numpy.ndarray: (azimuths,) int64 time of each row (µs)")
      .def_property_readonly(
          "measured",
          [](py::object self) {
            auto& s = self.cast<PolarScan&>();
            return view(s.measured, self, {s.azimuths});
          },
          "numpy.ndarray: (azimuths,) uint8, 1 where the sensor measured the row, 0 where it interpolated it");
  bindPolarScanRows(c);
}

void bindPolarScanRows(py::class_<PolarScan, ScanPtr>& c) {
  c.def_property_readonly(
       "encoder",
       [](py::object self) {
         auto& s = self.cast<PolarScan&>();
         return view(s.encoder, self, {static_cast<py::ssize_t>(s.encoder.size())});
       },
       "numpy.ndarray: (azimuths,) uint16 raw encoder counts (empty for RADIATE)")
      .def_property_readonly(
          "chirp_up",
          [](py::object self) {
            auto& s = self.cast<PolarScan&>();
            return view(s.chirp_up, self, {static_cast<py::ssize_t>(s.chirp_up.size())});
          },
          "numpy.ndarray: (azimuths,) uint8, 1 up-chirp, 0 down-chirp (Boreas from 2024); empty without chirp types")
      .def_readonly("range_resolution", &PolarScan::range_resolution, "metres per bin")
      .def_readonly("range_offset_bins", &PolarScan::range_offset_bins)
      .def_readonly("stamp", &PolarScan::stamp, "the scan's reference time (µs)")
      .def_property_readonly(
          "ranges",
          [](const PolarScan& s) {
            py::array_t<double> r(s.bins);
            for (int b = 0; b < s.bins; ++b) r.mutable_data()[b] = s.rangeOf(b);
            return r;
          },
          "numpy.ndarray: (bins,) range of each bin (m)")
      .def("__repr__", [](const PolarScan& s) {
        return "PolarScan(stamp=" + std::to_string(s.stamp) + ", azimuths=" + std::to_string(s.azimuths) +
               ", bins=" + std::to_string(s.bins) + ", range_resolution=" + std::to_string(s.range_resolution) + ")";
      });
}

void bindScanReaders(py::module_& m) {
  m.def(
      "read_oxford_scan",
      [](const std::filesystem::path& path_arg, const py::kwargs& kw) {
        const std::string path = path_arg.string();
        const auto o = withKeywords(OxfordPolarOptions{}, kw, "read_oxford_scan");
        return readScan([&] { return readOxfordPolarPng(path, o); });
      },
      py::arg("path"),
      "An Oxford Radar RobotCar polar PNG (its row layout: timestamp, encoder, flag, then power). "
      "Keywords: OxfordPolarOptions (convention, encoder_size, expected_bins).");
  m.def(
      "read_radiate_scan",
      [](const std::filesystem::path& path_arg, std::int64_t frame_time_us, const py::kwargs& kw) {
        const std::string path = path_arg.string();
        const auto o = withKeywords(RadiatePolarOptions{}, kw, "read_radiate_scan");
        return readScan([&] { return readRadiatePolarPng(path, frame_time_us, o); });
      },
      py::arg("path"), py::arg("frame_time_us") = 0,
      "A RADIATE Navtech_Polar PNG (no row metadata: rows spread over the sweep from frame_time_us). "
      "Keywords: RadiatePolarOptions.");
  m.def(
      "read_boreas_scan",
      [](const std::filesystem::path& path_arg, const py::kwargs& kw) {
        const std::string path = path_arg.string();
        const auto o = withKeywords(BoreasPolarOptions{}, kw, "read_boreas_scan");
        o.validate();
        return readScan([&] { return readBoreasPolarPng(path, o); });
      },
      py::arg("path"),
      "A Boreas radar PNG as pyboreas reads it (the bin by the file name's date, near bins zeroed, "
      "chirp types from the flag bytes). Keywords: BoreasPolarOptions.");
}

void bindPolarScan(py::module_& m) {
  bindPolarScanClass(m);
  bindScanReaders(m);
}

void bindTrajectory(py::module_& m) {
  py::class_<Trajectory>(m, "Trajectory",
                         "Poses of the vehicle frame in a fixed world frame, with timestamps (s) when known.\n\n"
                         "Trajectory(poses, stamps=None): poses (N, 4, 4), (N, 3, 3) SE(2) or (N, 3) x, y, yaw.")
      .def(py::init([](const py::object& poses, const py::object& stamps) {
             return toTrajectory(poses, stamps, "Trajectory");
           }),
           py::arg("poses"), py::arg("stamps") = py::none())
      .def("__len__", &Trajectory::size)
      .def_property_readonly("poses", &posesArray, "numpy.ndarray: (N, 4, 4) float64 homogeneous poses")
      .def_property_readonly("stamps", &stampsArray, "numpy.ndarray: (N,) seconds, or empty")
      .def_readonly("projected_rotations", &Trajectory::projected_rotations,
                    "int: rotation blocks of the file read that were not orthonormal (rounded) and were projected")
      .def_readonly("max_rotation_deviation", &Trajectory::max_rotation_deviation,
                    "float: the largest max|R^T R - I| among them")
      .def_property_readonly(
          "xy_yaw",
          [](const Trajectory& t) {
            py::array_t<double> a({static_cast<py::ssize_t>(t.size()), py::ssize_t{3}});
            for (std::size_t i = 0; i < t.size(); ++i) {
              const Pose2 p = toPose2(t.poses[i]);
              std::copy(p.data(), p.data() + 3, a.mutable_data() + 3 * i);
            }
            return a;
          },
          "numpy.ndarray: (N, 3) planar x, y, yaw of each pose")
      .def(
          "pose_at",
          [](const Trajectory& t, double time) -> py::object {
            Eigen::Isometry3d T;
            if (!t.poseAt(time, &T)) return py::none();
            return py::cast(Eigen::Matrix4d(T.matrix()));
          },
          py::arg("t"), "The 4x4 pose at time t (s), interpolated; None outside the stamps or without them.")
      .def("__repr__", [](const Trajectory& t) {
        return "Trajectory(" + std::to_string(t.size()) + " poses" + (t.hasStamps() ? ", stamped)" : ")");
      });
  m.def(
      "read_trajectory",
      [](const std::filesystem::path& path_arg, const std::string& format) {
        const std::string path = path_arg.string();
        const TrajectoryFormat f = parseTrajectoryFormat(format);
        py::gil_scoped_release release;
        return readTrajectory(path, f);
      },
      py::arg("path"), py::arg("format") = "auto",
      "A KITTI, TUM or Boreas-leaderboard file, or a Boreas pose CSV (format auto, kitti, tum or boreas).");
  m.def(
      "write_trajectory",
      [](const std::filesystem::path& path_arg, const Trajectory& t, const std::string& format) {
        const std::string path = path_arg.string();
        const TrajectoryFormat f = parseTrajectoryFormat(format);
        py::gil_scoped_release release;
        writeTrajectory(path, t, f);
      },
      py::arg("path"), py::arg("trajectory"), py::arg("format") = "tum",
      "Writes as radar_odometry --out does (kitti, tum or boreas; replaced atomically).");
}

void bindScanningSequence(py::module_& m) {
  py::class_<ScanningSequence>(m, "ScanningSequence",
                               "A scanning-radar sequence directory (radar_ndt/io/scanning_sequence.h).\n\n"
                               "ScanningSequence(path, format='oxford', **ScanningSequenceOptions): oxford, radiate or "
                               "boreas.")
      .def(py::init([](const std::filesystem::path& dir_arg, const std::string& format, const py::kwargs& kw) {
             const std::string dir = dir_arg.string();
             const auto o = withKeywords(ScanningSequenceOptions{}, kw, "ScanningSequence");
             const ScanFormat f = parseEnum<ScanFormat>(format);
             py::gil_scoped_release release;
             return std::make_unique<ScanningSequence>(dir, f, o);
           }),
           py::arg("path"), py::arg("format") = "oxford")
      .def("__len__", &ScanningSequence::size)
      .def_property_readonly("name", &ScanningSequence::name)
      .def_property_readonly("format", [](const ScanningSequence& s) { return std::string(toString(s.format())); })
      .def_property_readonly("period", &ScanningSequence::periodSeconds, "median interval between scans (s)")
      .def_property_readonly(
          "stamps",
          [](const ScanningSequence& s) {
            py::array_t<std::int64_t> a(static_cast<py::ssize_t>(s.size()));
            for (std::size_t k = 0; k < s.size(); ++k) a.mutable_data()[k] = s.stamp(k);
            return a;
          },
          "numpy.ndarray: (N,) int64 reference time of each scan (µs)")
      .def("path", &ScanningSequence::path, py::arg("k"))
      .def(
          "load",
          [](const ScanningSequence& s, std::size_t k) {
            if (k >= s.size()) throw py::index_error("scan " + std::to_string(k) + " of " + std::to_string(s.size()));
            return readScan([&] { return s.load(k); });
          },
          py::arg("k"), "Decodes scan k (IoError naming the file).")
      .def_property_readonly("ground_truth", &ScanningSequence::groundTruth,
                             "the dataset's SE(2) ground truth in the vehicle frame (empty without one)")
      .def_property_readonly("index_problems", &ScanningSequence::indexProblems);
}

py::dict sceneDict(const NuScenesScene& s) {
  py::dict d;
  d["name"] = s.name;
  d["token"] = s.token;
  d["description"] = s.description;
  d["log_token"] = s.log_token;
  d["first_timestamp_us"] = s.first_timestamp_us;
  d["last_timestamp_us"] = s.last_timestamp_us;
  return d;
}

py::dict sweepDict(const NuScenesSweep& s) {
  py::dict d;
  d["token"] = s.token;
  d["channel"] = s.channel;
  d["channel_index"] = s.channel_index;
  d["timestamp_us"] = s.timestamp_us;
  d["path"] = s.path;
  d["is_key_frame"] = s.is_key_frame;
  d["sensor_to_ego"] = Eigen::Matrix4d(s.sensor_to_ego.matrix());
  d["ego_to_global"] = Eigen::Matrix4d(s.ego_to_global.matrix());
  return d;
}

void bindNuScenesDataset(py::module_& m) {
  py::class_<NuScenesDataset, std::shared_ptr<NuScenesDataset>>(
      m, "NuScenesDataset",
      "The tables of a nuScenes-layout dataroot (radar_ndt/io/nuscenes.h).\n\nNuScenesDataset(dataroot, version='').")
      .def(py::init([](const std::filesystem::path& root_arg, const std::string& version) {
             const std::string root = root_arg.string();
             py::gil_scoped_release release;
             return std::make_shared<NuScenesDataset>(root, version);
           }),
           py::arg("dataroot"), py::arg("version") = "")
      .def_property_readonly("dataroot", &NuScenesDataset::dataroot)
      .def_property_readonly("scenes",
                             [](const NuScenesDataset& d) {
                               py::list l;
                               for (const auto& s : d.scenes()) l.append(sceneDict(s));
                               return l;
                             })
      .def_property_readonly("radar_channels", &NuScenesDataset::radarChannels)
      .def(
          "radar_sweeps",
          [](const NuScenesDataset& d, const std::string& scene) {
            py::list l;
            for (const auto& s : d.radarSweeps(d.scene(scene))) l.append(sweepDict(s));
            return l;
          },
          py::arg("scene"), "Every radar sweep of a scene in time order, as dicts (4x4 calibration and ego pose).");

  m.def(
      "read_nuscenes_pcd",
      [](const std::filesystem::path& path_arg, std::uint16_t sensor_id, const py::kwargs& kw) {
        const std::string path = path_arg.string();
        const auto filter = withKeywords(NuScenesRadarFilter{}, kw, "read_nuscenes_pcd");
        pcl::PointCloud<PointRadar> cloud;
        {
          py::gil_scoped_release release;
          cloud = readNuScenesRadarPcd(path, filter, sensor_id);
        }
        return toArray(cloud);
      },
      py::arg("path"), py::arg("sensor_id") = 0,
      "One nuScenes radar PCD as an (N, 11) array of POINT_FIELDS in the sensor frame (doppler: the radial "
      "velocity). Keywords: NuScenesRadarFilter (max_range, invalid_states, dyn_props, ambig_states).");
}

void bindRadarCycles(py::module_& m) {
  py::class_<RadarSweepData>(m, "RadarSweep", "One radar's sweep of a cycle, points in the sensor frame.")
      .def_readonly("timestamp_us", &RadarSweepData::timestamp_us)
      .def_readonly("sensor_id", &RadarSweepData::sensor_id)
      .def_property_readonly("sensor_to_vehicle",
                             [](const RadarSweepData& s) { return Eigen::Matrix4d(s.sensor_to_vehicle.matrix()); })
      .def_property_readonly("points", [](const RadarSweepData& s) { return toArray(s.points); });
  py::class_<RadarCycle>(m, "RadarCycle", "One sweep of every radar, clocked by the reference radar.")
      .def_readonly("timestamp_us", &RadarCycle::timestamp_us)
      .def_readonly("sweeps", &RadarCycle::sweeps);

  py::class_<NuScenesRadarSequence>(m, "NuScenesRadarSequence",
                                    "A nuScenes scene as radar cycles (radar_ndt/io/nuscenes_sequence.h).\n\n"
                                    "NuScenesRadarSequence(dataset, scene, **NuScenesSequenceOptions).")
      .def(py::init([](const NuScenesDataset& d, const std::string& scene, const py::kwargs& kw) {
             const auto o = withKeywords(NuScenesSequenceOptions{}, kw, "NuScenesRadarSequence");
             return std::make_unique<NuScenesRadarSequence>(d, d.scene(scene), o);
           }),
           py::arg("dataset"), py::arg("scene"))
      .def("__len__", &NuScenesRadarSequence::size)
      .def_property_readonly("scene", &NuScenesRadarSequence::sceneName)
      .def_property_readonly("reference_channel", &NuScenesRadarSequence::referenceChannel)
      .def_property_readonly("period", &NuScenesRadarSequence::periodSeconds)
      .def("timestamp", &NuScenesRadarSequence::timestamp, py::arg("k"))
      .def_property_readonly("ground_truth", &NuScenesRadarSequence::groundTruthTrajectory,
                             "SE(2) ego poses of the cycles, relative to the first")
      .def_property_readonly("silences", &NuScenesRadarSequence::silences)
      .def(
          "load",
          [](const NuScenesRadarSequence& s, std::size_t k) {
            if (k >= s.size()) throw py::index_error("cycle " + std::to_string(k) + " of " + std::to_string(s.size()));
            std::vector<std::string> problems;
            RadarCycle c;
            {
              py::gil_scoped_release release;
              c = s.load(k, &problems);
            }
            return py::make_tuple(std::move(c), problems);
          },
          py::arg("k"),
          "Reads cycle k: (RadarCycle, problems), a sweep that cannot be read left out and described in problems.");
}

/// A time series as a dict of two arrays: stamps (µs, int64) and values.
py::dict seriesArrays(const TimeSeries& s) {
  py::dict d;
  d["stamps_us"] = py::array_t<std::int64_t>(static_cast<py::ssize_t>(s.size()), s.stamps_us.data());
  d["values"] = py::array_t<double>(static_cast<py::ssize_t>(s.size()), s.values.data());
  return d;
}

void bindCanBus(py::module_& m) {
  m.def(
      "read_can_bus",
      [](const std::filesystem::path& dataroot, const std::string& scene) -> py::object {
        const auto s = readNuScenesCanBus(dataroot.string(), scene);
        if (!s) return py::none();
        py::dict d;
        d["yaw_rate"] = seriesArrays(s->yaw_rate);
        d["rear_wheel_rpm"] = seriesArrays(s->rear_wheel_rpm);
        d["dropped"] = s->dropped;
        return d;
      },
      py::arg("dataroot"), py::arg("scene"),
      "The nuScenes CAN bus of `scene` (radar_ndt/io/nuscenes_can_bus.h): {'yaw_rate': {'stamps_us', "
      "'values' (rad/s)}, 'rear_wheel_rpm': {...}, 'dropped'}, or None when dataroot/can_bus is not there. "
      "IoError naming the file for a missing or malformed message file.");
}

void bindNuScenes(py::module_& m) {
  bindNuScenesDataset(m);
  bindRadarCycles(m);
  bindCanBus(m);
}

}  // namespace

void bindIo(py::module_& m) {
  bindPolarScan(m);
  bindTrajectory(m);
  bindScanningSequence(m);
  bindNuScenes(m);
}

}  // namespace python
}  // namespace radar_ndt
