// SPDX-License-Identifier: Apache-2.0
// The status bar's and run's name for a scene's elastic model says which FEM element it is.

#include "app/ElasticModelWords.h"

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

TEST(ElasticModelWords, NameTheSpringsOrTheFemWithItsStrainCells) {
  SceneDescription scene;
  EXPECT_EQ(elasticModelWords(scene), "springs");
  scene.model = "fem";
  EXPECT_EQ(elasticModelWords(scene), "tets (FEM)");
  scene.strainCells = "faces";
  EXPECT_EQ(elasticModelWords(scene), "tets (FEM, strain per face)");
  scene.strainCells = "nodes";
  EXPECT_EQ(elasticModelWords(scene), "tets (FEM, strain per node)");
}

}  // namespace
}  // namespace tissuesim
