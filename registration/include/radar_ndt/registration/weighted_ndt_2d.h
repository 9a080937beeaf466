#pragma once
// radar_ndt::WeightedNDT2D: the weighted probabilistic 2D NDT of the paper (Section III-C/D) as a
// pcl::Registration subclass, so it swaps with pcl::IterativeClosestPoint and
// pcl::NormalDistributionsTransform through a pcl::Registration<...>::Ptr.
//
// Target model (built once, in setInputTarget): square cells of side g; per cell the weighted mean
// μ = Σ wᵢpᵢ / Σ wᵢ and the probabilistic covariance Σ = Σ wᵢ[(pᵢ−μ)(pᵢ−μ)ᵀ + Σᵢ] / Σ wᵢ
// (Hong & Lee 2017), weights wᵢ = max(pᵢ − s, 0) (eq. 1), Σᵢ the point's own covariance.
// Cost: each source point scored against the cells near it, score = Σ wᵢ exp(−½ qᵀ Σ⁻¹ q) with
// q = T(x)pᵢ − μ and wᵢ = max(pᵢ − s, 0) · exp(−½(σx + σy)) (eq. 2); maximised by Newton's method on
// SE(2) with the analytic gradient and Hessian (Biber & Straßer 2003).
//
// Point types: radar_ndt::PointRadar (power, covariance), pcl::PointXYZI (intensity = power, no
// covariance), pcl::PointXYZ (power 1, no covariance); fields are detected at compile time. The
// template is compiled once in the library for these three; for other point types include
// <radar_ndt/registration/impl/weighted_ndt_2d.hpp>.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_types.h>
#include <pcl/registration/registration.h>
#include <pcl/search/kdtree.h>

#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// How a source point finds the target distributions it is scored against.
enum class CellLookup {
  /// One grid; a point is scored against the 2x2 block of cells whose centres are nearest to it
  /// (the cell it falls in and the three neighbours on its side), as ndt_omp's direct search does.
  Neighbours,
  /// Biber's four overlapping grids, shifted by half a cell in x, y and both; a point is scored
  /// against the cell it falls in, in each grid.
  OverlappingGrids,
};

namespace detail {
/// pcl::search::KdTree that builds its tree only when first searched. pcl::Registration::align
/// rebuilds the target kd-tree for every new target; NDT never searches it, so the only user left
/// is pcl::Registration::getFitnessScore(), which then pays for the tree when (and if) it is called.
template <typename PointT>
class LazyKdTree : public pcl::search::KdTree<PointT> {
 public:
  using Base = pcl::search::KdTree<PointT>;
  using typename Base::PointCloudConstPtr;
  using IndicesConstPtr = pcl::IndicesConstPtr;
  using Base::nearestKSearch;
  using Base::radiusSearch;

  void setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices = IndicesConstPtr()) override {
    this->input_ = cloud;
    this->indices_ = indices;
    built_ = false;
  }
  int nearestKSearch(const PointT& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    build();
    return Base::nearestKSearch(point, k, k_indices, k_sqr_distances);
  }
  int radiusSearch(const PointT& point, double radius, pcl::Indices& k_indices, std::vector<float>& k_sqr_distances,
                   unsigned int max_nn = 0) const override {
    build();
    return Base::radiusSearch(point, radius, k_indices, k_sqr_distances, max_nn);
  }

 private:
  void build() const {
    if (!built_ && this->input_) {
      const_cast<LazyKdTree*>(this)->Base::setInputCloud(this->input_, this->indices_);
      built_ = true;
    }
  }
  mutable bool built_ = false;
};

/// A 2D integer cell or voxel coordinate packed into one 64-bit key, and the hash both maps below
/// use (splitmix64's finaliser).
inline std::uint64_t packKey(std::int32_t ix, std::int32_t iy) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix)) << 32) | static_cast<std::uint32_t>(iy);
}
inline void unpackKey(std::uint64_t key, std::int32_t& ix, std::int32_t& iy) {
  ix = static_cast<std::int32_t>(static_cast<std::uint32_t>(key >> 32));
  iy = static_cast<std::int32_t>(static_cast<std::uint32_t>(key & 0xffffffffu));
}
inline std::uint64_t hashKey(std::uint64_t k) {
  k ^= k >> 30;
  k *= 0xbf58476d1ce4e5b9ULL;
  k ^= k >> 27;
  k *= 0x94d049bb133111ebULL;
  k ^= k >> 31;
  return k;
}

/// Open-addressing hash from a 2D integer key to up to four cell indices (-1 = none). Memory is
/// linear in the number of keys; there is no dense grid over the extent.
class CellIndexHash {
 public:
  void clear();
  void reserve(std::size_t keys);
  /// Adds `cell` to the slot list of key (ix, iy).
  void add(std::int32_t ix, std::int32_t iy, std::int32_t cell);
  /// After the last add(): when the keys' bounding box is small against their count (a scan or a
  /// submap, not a long sparse track), also lay them out in a dense row-major table, so find() is
  /// an index computation instead of a hash probe. A later add() drops the table.
  void finalize();
  /// The four slots of (ix, iy), or nullptr when the key is absent.
  inline const std::int32_t* find(std::int32_t ix, std::int32_t iy) const {
    if (!dense_.empty()) {
      const std::int64_t dx = static_cast<std::int64_t>(ix) - dense_x0_, dy = static_cast<std::int64_t>(iy) - dense_y0_;
      if (dx < 0 || dy < 0 || dx >= dense_w_ || dy >= dense_h_) return nullptr;
      const std::int32_t* slots = dense_[static_cast<std::size_t>(dy * dense_w_ + dx)].slots;
      return slots[0] >= 0 ? slots : nullptr;
    }
    if (size_ == 0) return nullptr;
    const std::uint64_t key = packKey(ix, iy);
    std::size_t h = hashKey(key) & mask_;
    while (entries_[h].slots[0] >= 0) {
      if (entries_[h].key == key) return entries_[h].slots;
      h = (h + 1) & mask_;
    }
    return nullptr;
  }
  std::size_t size() const { return size_; }
  std::size_t memoryBytes() const;

 private:
  /// Key and its four slots in one 24-byte entry: a lookup touches one cache line. An entry is
  /// empty while slots[0] < 0 (an occupied key always has a first slot).
  struct Entry {
    std::uint64_t key;
    std::int32_t slots[4];
  };
  struct Slots {
    std::int32_t slots[4];
  };
  std::vector<Entry> entries_;
  std::size_t size_ = 0;
  std::size_t mask_ = 0;
  std::vector<Slots> dense_;  ///< empty unless finalize() found the keys compact
  std::int64_t dense_x0_ = 0, dense_y0_ = 0, dense_w_ = 0, dense_h_ = 0;
};

/// Open-addressing map from a packed 2D integer key to a dense index (0, 1, 2, … in order of first
/// insertion), for grouping points by cell or voxel in one pass without sorting.
class KeyIndexMap {
 public:
  explicit KeyIndexMap(std::size_t expected_keys) {
    std::size_t cap = 16;
    while (cap < 2 * expected_keys) cap <<= 1;
    keys_.assign(cap, 0);
    index_.assign(cap, -1);
    mask_ = cap - 1;
  }
  /// The index of key (ix, iy), inserting it with index `next` when absent (then `inserted` is true).
  inline std::int32_t findOrInsert(std::int32_t ix, std::int32_t iy, std::int32_t next, bool& inserted) {
    if (2 * (count_ + 1) > keys_.size()) grow();
    const std::uint64_t key = packKey(ix, iy);
    std::size_t h = hashKey(key) & mask_;
    while (index_[h] >= 0) {
      if (keys_[h] == key) {
        inserted = false;
        return index_[h];
      }
      h = (h + 1) & mask_;
    }
    keys_[h] = key;
    index_[h] = next;
    ++count_;
    inserted = true;
    return next;
  }

 private:
  void grow() {
    std::vector<std::uint64_t> keys;
    std::vector<std::int32_t> index;
    keys.swap(keys_);
    index.swap(index_);
    keys_.assign(2 * keys.size(), 0);
    index_.assign(2 * keys.size(), -1);
    mask_ = keys_.size() - 1;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (index[i] < 0) continue;
      std::size_t h = hashKey(keys[i]) & mask_;
      while (index_[h] >= 0) h = (h + 1) & mask_;
      keys_[h] = keys[i];
      index_[h] = index[i];
    }
  }
  std::vector<std::uint64_t> keys_;
  std::vector<std::int32_t> index_;
  std::size_t mask_ = 0, count_ = 0;
};

/// One target distribution: weighted mean and inverse covariance (upper triangle).
struct NdtCell {
  double mx, my;      ///< μ
  double ixx, ixy, iyy;  ///< Σ⁻¹
  double weight;      ///< Σ wᵢ of the points that built it
};

/// The target's distributions at one grid size, with the lookup from a point to its cells.
struct NdtGrid {
  double resolution = 0;
  CellLookup lookup = CellLookup::Neighbours;
  std::vector<NdtCell> cells;
  CellIndexHash index;
  /// Lookup keys are floor(x · key_scale + key_shift): the nearest grid vertex (Neighbours) or the
  /// half-size cell (OverlappingGrids).
  double key_scale = 1, key_shift = 0;
  void setLookup(double g, CellLookup l) {
    resolution = g;
    lookup = l;
    key_scale = l == CellLookup::Neighbours ? 1.0 / g : 2.0 / g;
    key_shift = l == CellLookup::Neighbours ? 0.5 : 0.0;
  }
  /// Up to four cells to score a point at (x, y) against; returns the slot array or nullptr.
  inline const std::int32_t* cellsNear(double x, double y) const {
    const double u = x * key_scale + key_shift, v = y * key_scale + key_shift;
    if (!(std::abs(u) < 1e9 && std::abs(v) < 1e9)) return nullptr;  // far away or NaN: no key
    return index.find(static_cast<std::int32_t>(std::floor(u)), static_cast<std::int32_t>(std::floor(v)));
  }
};

/// A source point reduced to what the cost needs.
struct WeightedPoint2D {
  double x, y, w;
};
}  // namespace detail

template <typename PointSource, typename PointTarget>
class WeightedNDT2D : public pcl::Registration<PointSource, PointTarget, float> {
 public:
  using Base = pcl::Registration<PointSource, PointTarget, float>;
  using typename Base::Matrix4;
  using typename Base::PointCloudSource;
  using typename Base::PointCloudTarget;
  using PointCloudTargetConstPtr = typename PointCloudTarget::ConstPtr;
  using Ptr = pcl::shared_ptr<WeightedNDT2D<PointSource, PointTarget>>;
  using ConstPtr = pcl::shared_ptr<const WeightedNDT2D<PointSource, PointTarget>>;

  WeightedNDT2D();
  ~WeightedNDT2D() override = default;

  /// Sets the target and builds its cell model (all grid sizes), once per target. The setters
  /// below that change the model (grid sizes, power shift, eigenvalue ratio, minimum points, cell
  /// lookup) only mark it stale: it is rebuilt once, at the next setInputTarget() or align(), so
  /// changing settings and target together costs one build.
  void setInputTarget(const PointCloudTargetConstPtr& cloud) override;

  /// Grid size g (m), single stage. Default 3.0 m.
  void setResolution(float g) { setResolutions({g}); }
  /// Coarse-to-fine grid sizes (e.g. {9, 6, 4}); each stage starts from the previous result.
  void setResolutions(const std::vector<float>& sizes);
  const std::vector<float>& getResolutions() const { return resolutions_; }
  float getResolution() const { return resolutions_.back(); }

  /// Power shift s of eq. (1)-(2): weights max(p − s, 0). Default 0.
  void setPowerShift(float s);
  float getPowerShift() const { return power_shift_; }
  /// Whether the matching weights of eq. (2) use the shift too (the paper, and the default) or are
  /// p·exp(−½(σx + σy)) with the shift kept for the cells of eq. (1) only (an ablation: on the
  /// simulated drives the source's shift is what costs accuracy; README, "Scanning radar odometry").
  void setShiftSourceWeights(bool on) { shift_source_ = on; }
  bool getShiftSourceWeights() const { return shift_source_; }

  /// A cell's smallest covariance eigenvalue is raised to at least ratio × its largest. Default 0.01.
  void setEigenvalueRatio(double ratio);
  double getEigenvalueRatio() const { return eigen_ratio_; }

  /// Cells built from fewer points are dropped. Default 3.
  void setMinPointsPerCell(int n);
  int getMinPointsPerCell() const { return min_points_per_cell_; }

  /// Source points falling in one voxel of this size (m) are merged into one point at their
  /// weighted centroid carrying their summed weight, before matching. 0 turns it off. Default
  /// 0.25 m: small against the cells' spread, it leaves the cost almost unchanged and cuts the
  /// evaluation time with the point count (README, "Matcher speed").
  void setSourceVoxelSize(double size_m) { source_voxel_size_ = std::max(0.0, size_m); }
  double getSourceVoxelSize() const { return source_voxel_size_; }

  void setCellLookup(CellLookup lookup);
  CellLookup getCellLookup() const { return lookup_; }

  /// Newton steps are limited to this translation (m, default: half the grid size) and rotation
  /// (rad, default 0.2) before the line search.
  void setMaxStep(double translation_m, double rotation_rad) {
    max_step_translation_ = translation_m;
    max_step_rotation_ = rotation_rad;
  }

  /// Newton iterations of the last align(), summed over coarse-to-fine stages (PCL NDT's name).
  /// setMaximumIterations() bounds the iterations of each grid stage (default 35); a stage first
  /// iterates on a 1-in-4 subsample of the source, then on all points, within that one budget.
  int getFinalNumIteration() const { return final_num_iterations_; }
  /// Hessian of the negative NDT score at the solution, in (x, y, yaw).
  const Eigen::Matrix3d& getFinalHessian() const { return final_hessian_; }
  /// 3x3 covariance of (x, y, yaw): the inverse of the weighted point-to-distribution information
  /// Σᵢ wᵢ eᵢ Jᵢᵀ Σ⁻¹ Jᵢ (eᵢ the point's Gaussian score). Optimistic (treats points as independent);
  /// infinite diagonal when the problem is degenerate.
  const Eigen::Matrix3d& getPoseCovariance() const { return pose_covariance_; }
  /// Source points that found at least one cell at the solution (last stage).
  std::size_t getNumMatchedPoints() const { return num_matched_points_; }
  /// Final NDT score Σ wᵢ exp(−½ qᵀΣ⁻¹q) (larger is better). pcl::Registration::getFitnessScore()
  /// keeps PCL's meaning (mean squared nearest-neighbour distance) and builds a kd-tree to get it.
  double getNdtScore() const { return final_score_; }
  /// Source points the cost uses: finite, positive weight, after the voxel merge.
  std::size_t getNumSourcePoints() const { return source_points_.size(); }
  /// Cells in the target model of the finest grid, and its memory (bytes), as last built.
  std::size_t getNumCells() const { return grids_.empty() ? 0 : grids_.back().cells.size(); }
  std::size_t getTargetModelBytes() const;
  /// True when the last align() stopped because the problem was degenerate (too few matched
  /// points, a rank-deficient Hessian, no target cells).
  bool wasDegenerate() const { return degenerate_; }

 protected:
  using Base::converged_;
  using Base::final_transformation_;
  using Base::input_;
  using Base::max_iterations_;
  using Base::nr_iterations_;
  using Base::previous_transformation_;
  using Base::reg_name_;
  using Base::target_;
  using Base::transformation_;
  using Base::transformation_epsilon_;
  using Base::transformation_rotation_epsilon_;

  void computeTransformation(PointCloudSource& output, const Matrix4& guess) override;

  /// Value, gradient and Hessian of the negative score at pose x = (tx, ty, yaw) on one grid.
  /// Deterministic: terms are summed in source-point order. `stride` > 1 uses every stride-th point.
  double evaluate(const detail::NdtGrid& grid, const Eigen::Vector3d& x, Eigen::Vector3d* gradient,
                  Eigen::Matrix3d* hessian, std::size_t* matched = nullptr,
                  Eigen::Matrix3d* information = nullptr, std::size_t stride = 1) const;

  void buildTargetModel();
  void buildGrid(detail::NdtGrid& grid, double resolution) const;
  void prepareSource();

  std::vector<float> resolutions_{3.0f};
  float power_shift_ = 0.0f;
  bool shift_source_ = true;
  double eigen_ratio_ = 0.01;
  int min_points_per_cell_ = 3;
  CellLookup lookup_ = CellLookup::Neighbours;
  double source_voxel_size_ = 0.25;
  double max_step_translation_ = -1;  // < 0: half the grid size
  double max_step_rotation_ = 0.2;

  std::vector<detail::NdtGrid> grids_;  // one per resolution, coarse to fine
  bool model_stale_ = false;            // a setting changed since grids_ was built
  std::vector<detail::WeightedPoint2D> source_points_;
  std::vector<std::int32_t> voxel_keys_;   // scratch of prepareSource's voxel merge: each point's key
  std::vector<std::int32_t> voxel_table_;  // and the dense table of voxel slots
  std::vector<detail::WeightedPoint2D> voxel_merged_;  // and the merged points (then the previous source)

  int final_num_iterations_ = 0;
  Eigen::Matrix3d final_hessian_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d pose_covariance_ = Eigen::Matrix3d::Zero();
  std::size_t num_matched_points_ = 0;
  double final_score_ = 0;
  bool degenerate_ = false;
};

}  // namespace radar_ndt

// The library compiles the template for these; others include impl/weighted_ndt_2d.hpp.
#ifndef RADAR_NDT_WEIGHTED_NDT_2D_INSTANTIATE
extern template class radar_ndt::WeightedNDT2D<pcl::PointXYZ, pcl::PointXYZ>;
extern template class radar_ndt::WeightedNDT2D<pcl::PointXYZI, pcl::PointXYZI>;
extern template class radar_ndt::WeightedNDT2D<radar_ndt::PointRadar, radar_ndt::PointRadar>;
// PCL templates for PointRadar that PCL does not precompile; compiled once in the library.
extern template class pcl::PCLBase<radar_ndt::PointRadar>;
extern template class pcl::search::KdTree<radar_ndt::PointRadar>;
extern template class pcl::Registration<radar_ndt::PointRadar, radar_ndt::PointRadar, float>;
#endif
