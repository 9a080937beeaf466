// An outside project: aligns two clouds with the installed RadarNDT through pcl::Registration, and
// through the odometry's matcher factory, with the 0.2 include paths; the same planar pair with the
// same code three times, WeightedNDT2D, then pcl::IterativeClosestPoint and
// pcl::NormalDistributionsTransform in its place; and a 6-DoF pair the same way, WeightedNDT3D,
// then pcl::NormalDistributionsTransform and pcl::GeneralizedIterativeClosestPoint (the one line a
// user changes). Each run's output cloud is its source moved by its result.
#include <cmath>
#include <cstdio>
#include <random>

#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>
#include <radar_ndt/odometry/matcher.h>
#include <radar_ndt/registration/weighted_ndt_2d.h>
#include <radar_ndt/registration/weighted_ndt_3d.h>
#include <radar_ndt/se2.h>
#include <radar_ndt/se3.h>

namespace {

using Cloud3 = pcl::PointCloud<pcl::PointXYZ>;

/// A room's corner (floor and two walls) with a few boxes, as a target; the source is the same
/// scene seen from a pose moved by a 6-DoF motion, sampled anew.
Cloud3::Ptr scene(unsigned seed, const Eigen::Isometry3d& seen_from) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 12.f), n(-0.02f, 0.02f);
  Cloud3::Ptr c(new Cloud3);
  for (int i = 0; i < 6000; ++i) {
    const float a = u(rng), b = 0.25f * u(rng);
    Eigen::Vector3d p;
    switch (i % 4) {
      case 0: p = Eigen::Vector3d(a, u(rng), n(rng)); break;
      case 1: p = Eigen::Vector3d(a, n(rng), b); break;
      case 2: p = Eigen::Vector3d(n(rng), a, b); break;
      default: p = Eigen::Vector3d(4.0 + 4.0 * (i % 3) + 0.1 * b, 3.0 + 3.0 * (i % 2) + 0.1 * a, 0.5 * b); break;
    }
    const Eigen::Vector3d q = seen_from.inverse() * p;
    c->push_back(pcl::PointXYZ(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())));
  }
  return c;
}

/// Whether `out` is `source` moved by `T`.
bool isSourceMoved(const Cloud3& out, const Cloud3& source, const Eigen::Matrix4f& T) {
  if (out.size() != source.size()) return false;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Eigen::Vector3f moved = T.topLeftCorner<3, 3>() * source[i].getVector3fMap() + T.topRightCorner<3, 1>();
    if ((out[i].getVector3fMap() - moved).norm() > 1e-4f) return false;
  }
  return true;
}

/// The caller's code, written once against pcl::Registration: true when `reg` recovers `motion`.
bool recovers(const pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>::Ptr& reg, const Eigen::Isometry3d& motion) {
  const Cloud3::Ptr source = scene(2, motion);
  reg->setInputSource(source);
  reg->setInputTarget(scene(1, Eigen::Isometry3d::Identity()));
  reg->setMaxCorrespondenceDistance(2.0);
  Cloud3 aligned;
  reg->align(aligned);
  const bool moved = isSourceMoved(aligned, *source, reg->getFinalTransformation());
  const Eigen::Isometry3d est(reg->getFinalTransformation().cast<double>());
  const double t_err = (est.translation() - motion.translation()).norm();
  const double r_err = Eigen::AngleAxisd(est.linear().transpose() * motion.linear()).angle();
  std::printf("%s: converged %d, translation error %.3f m, rotation error %.3f deg\n", reg->getClassName().c_str(),
              reg->hasConverged() ? 1 : 0, t_err, r_err * 180.0 / radar_ndt::kPi);
  return moved && t_err < 0.05 && r_err < 0.01;
}

bool swapIn3D() {
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  motion.linear() = radar_ndt::expSO3(Eigen::Vector3d(0.02, -0.03, 0.06));
  motion.translation() << 0.4, -0.3, 0.1;
  bool ok = recovers(pcl::make_shared<radar_ndt::WeightedNDT3D<pcl::PointXYZ, pcl::PointXYZ>>(), motion);
  auto ndt = pcl::make_shared<pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ>>();
  ndt->setResolution(2.0f);
  ndt->setStepSize(0.5);
  ndt->setTransformationEpsilon(0.001);
  ok = recovers(ndt, motion) && ok;
  ok = recovers(pcl::make_shared<pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>>(), motion) && ok;
  return ok;
}

/// The planar pair with the same code three times: WeightedNDT2D must recover (dx, dy); PCL's ICP and
/// NDT must run through the same pointer and move their output with their result.
bool swapIn2D(const Cloud3::Ptr& source, const Cloud3::Ptr& target, float dx, float dy) {
  bool ok = true;
  for (int which = 0; which < 3; ++which) {
    pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>::Ptr reg;
    if (which == 0) reg.reset(new radar_ndt::WeightedNDT2D<pcl::PointXYZ, pcl::PointXYZ>);
    if (which == 1) reg.reset(new pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>);
    if (which == 2) {
      auto ndt = pcl::make_shared<pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ>>();
      ndt->setResolution(3.0f);
      reg = ndt;
    }
    reg->setInputSource(source);
    reg->setInputTarget(target);
    reg->setMaximumIterations(50);
    Cloud3 aligned;
    reg->align(aligned);
    const Eigen::Matrix4f T = reg->getFinalTransformation();
    const bool moved = isSourceMoved(aligned, *source, T), finite = T.allFinite();
    std::printf("%s (2D pair): t = (%.3f, %.3f)\n", reg->getClassName().c_str(), T(0, 3), T(1, 3));
    ok = ok && moved && finite;
    if (which == 0) ok = ok && reg->hasConverged() && std::abs(T(0, 3) - dx) < 0.02f && std::abs(T(1, 3) - dy) < 0.02f;
  }
  return ok;
}

}  // namespace

int main() {
  pcl::PointCloud<pcl::PointXYZ>::Ptr target(new pcl::PointCloud<pcl::PointXYZ>),
      source(new pcl::PointCloud<pcl::PointXYZ>);
  for (int i = 0; i < 400; ++i) {  // an L-shaped wall and a row of poles
    const float t = 0.05f * static_cast<float>(i);
    target->push_back(pcl::PointXYZ(t, 0.0f, 0.0f));
    target->push_back(pcl::PointXYZ(0.0f, t, 0.0f));
    target->push_back(pcl::PointXYZ(5.0f + 0.01f * static_cast<float>(i % 10), 4.0f * static_cast<float>(i % 5), 0.0f));
  }
  const float dx = 0.4f, dy = -0.3f;  // source = target moved by (-dx, -dy)
  for (const auto& p : *target) source->push_back(pcl::PointXYZ(p.x - dx, p.y - dy, 0.0f));

  pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>::Ptr reg(new radar_ndt::WeightedNDT2D<pcl::PointXYZ, pcl::PointXYZ>);
  reg->setInputSource(source);
  reg->setInputTarget(target);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  reg->align(aligned);
  const Eigen::Matrix4f T = reg->getFinalTransformation();
  std::printf("converged %d, t = (%.3f, %.3f)\n", reg->hasConverged() ? 1 : 0, T(0, 3), T(1, 3));
  const bool ok = reg->hasConverged() && std::abs(T(0, 3) - dx) < 0.02f && std::abs(T(1, 3) - dy) < 0.02f;

  // The same pair as PointRadar through the library's matcher factory (RadarNDT::radar_ndt).
  pcl::PointCloud<radar_ndt::PointRadar>::Ptr t2(new pcl::PointCloud<radar_ndt::PointRadar>),
      s2(new pcl::PointCloud<radar_ndt::PointRadar>);
  for (const auto& p : *target) t2->push_back(radar_ndt::PointRadar(p.x, p.y, 0.0f));
  for (const auto& p : *source) s2->push_back(radar_ndt::PointRadar(p.x, p.y, 0.0f));
  const radar_ndt::MatcherAdapter matcher = radar_ndt::makeMatcher(radar_ndt::MatcherOptions::forAutomotive());
  matcher.registration().setInputSource(s2);
  matcher.registration().setInputTarget(t2);
  pcl::PointCloud<radar_ndt::PointRadar> out;
  matcher.registration().align(out);
  const radar_ndt::Pose2 pose = radar_ndt::toPose2(matcher.registration().getFinalTransformation());
  std::printf("factory: converged %d, t = (%.3f, %.3f)\n", matcher.registration().hasConverged() ? 1 : 0, pose.x(),
              pose.y());
  const bool ok2 =
      matcher.registration().hasConverged() && std::abs(pose.x() - dx) < 0.02 && std::abs(pose.y() - dy) < 0.02;
  const bool ok3 = swapIn3D();
  const bool ok4 = swapIn2D(source, target, dx, dy);
  return ok && ok2 && ok3 && ok4 ? 0 : 1;
}
