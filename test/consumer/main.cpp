// An outside project: aligns two clouds with the installed RadarNDT through pcl::Registration, and
// through the odometry's matcher factory, with the 0.2 include paths.
#include <cmath>
#include <cstdio>

#include <radar_ndt/odometry/matcher.h>
#include <radar_ndt/registration/weighted_ndt_2d.h>
#include <radar_ndt/se2.h>

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
  return ok && ok2 ? 0 : 1;
}
