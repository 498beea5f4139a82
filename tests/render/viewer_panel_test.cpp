// The viewer panel's electrosurgery lines (surgery_status): what is on, what burns, and the blood
// lost, from a snapshot.
#include <gtest/gtest.h>

#include "trocar/render/viewer_panel.h"

namespace trocar {
namespace {

TEST(SurgeryStatus, NothingOnAndNothingBledSaysNothing) {
  ViewSnapshot snap;
  snap.instruments.resize(2);
  EXPECT_EQ(surgery_status(snap, {"hook", "cannula"}), "");
}

TEST(SurgeryStatus, NamesWhatIsOnAndAddsUpTheBloodLost) {
  ViewSnapshot snap;
  snap.instruments.resize(3);
  snap.vapour.resize(3);
  snap.instruments[0].energy = true;
  snap.vapour[0].burning = true;
  snap.instruments[1].suction = true;
  snap.instruments[1].irrigation = true;
  snap.instruments[2].energy = true;  // pedal down, touching nothing
  snap.wounds.push_back({0, 3, 0.8e-6, false});
  snap.wounds.push_back({1, 7, 0.45e-6, true});
  EXPECT_EQ(surgery_status(snap, {"hook", "cannula"}),
            "hook: energy on, burning\n"
            "cannula: suction, irrigation\n"
            "instrument 2: energy on\n"
            "blood lost 1.2 ml; 1 of 2 wounds bleeding");
}

}  // namespace
}  // namespace trocar
