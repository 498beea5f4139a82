// API smoke test (replaced by the real tests).
#include <gtest/gtest.h>

#include "trocar/collision/detector.h"

namespace trocar {
namespace {
TEST(CollisionApi, Compiles) {
  CollisionDetector d;
  std::vector<CollisionObject> objects;
  EXPECT_TRUE(d.detect(objects).empty());
}
}  // namespace
}  // namespace trocar
