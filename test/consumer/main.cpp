// An outside project: aligns two clouds with the installed RadarNDT through pcl::Registration.
#include <cmath>
#include <cstdio>

#include <radar_ndt/registration/weighted_ndt_2d.h>

int main() {
  pcl::PointCloud<pcl::PointXYZ>::Ptr target(new pcl::PointCloud<pcl::PointXYZ>), source(new pcl::PointCloud<pcl::PointXYZ>);
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
  return reg->hasConverged() && std::abs(T(0, 3) - dx) < 0.02f && std::abs(T(1, 3) - dy) < 0.02f ? 0 : 1;
}
