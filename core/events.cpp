#include "core/events.hpp"

namespace orthosonar {

const char* channel_topic(Channel c) {
  switch (c) {
    case Channel::kSonarHorizontal: return "/sonar/horizontal/ping";
    case Channel::kSonarVertical: return "/sonar/vertical/ping";
    case Channel::kImu: return "/imu/data";
    case Channel::kDvl: return "/dvl/velocity";
    case Channel::kDepth: return "/depth";
    case Channel::kTruthPose: return "/truth/pose";
    case Channel::kLabelsHorizontal: return "/sonar/horizontal/labels";
    case Channel::kLabelsVertical: return "/sonar/vertical/labels";
    case Channel::kGyro: return "/gyro";
  }
  return "?";
}

Channel channel_of(const Payload& p) {
  struct V {
    Channel operator()(const SonarPing& s) const {
      return s.mount == SonarMount::kHorizontal ? Channel::kSonarHorizontal : Channel::kSonarVertical;
    }
    Channel operator()(const DvlReading&) const { return Channel::kDvl; }
    Channel operator()(const ImuReading&) const { return Channel::kImu; }
    Channel operator()(const DepthReading&) const { return Channel::kDepth; }
    Channel operator()(const TruthPose&) const { return Channel::kTruthPose; }
    Channel operator()(const GyroReading&) const { return Channel::kGyro; }
    Channel operator()(const SonarLabels& l) const {
      return l.mount == SonarMount::kHorizontal ? Channel::kLabelsHorizontal : Channel::kLabelsVertical;
    }
  };
  return std::visit(V{}, p);
}

Time stamp_of(const Payload& p) {
  return std::visit([](const auto& x) { return x.stamp; }, p);
}

}  // namespace orthosonar
