// SPDX-License-Identifier: GPL-2.0-or-later
// The columns of the breakage event log (crush_event_log_kernel.h): the
// header line fix crush/particle writes, as the Python readers expect it.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "crush_event_log_kernel.h"

using namespace CrushKernels;

TEST(EventLog, HeaderLineWithoutEnergy)
{
  EXPECT_EQ(event_log_columns(false),
            "step time parent_tag parent_diameter x y z F_n F_lim partner generation");
}

TEST(EventLog, HeaderLineWithEnergy)
{
  EXPECT_EQ(event_log_columns(true),
            "step time parent_tag parent_diameter x y z F_n F_lim partner generation "
            "E_el_before E_el_after KE_before KE_frag0 KE_gain v_max n_steps");
}

TEST(EventLog, CountsMatchTheHeader)
{
  for (bool energy : {false, true}) {
    std::istringstream words(event_log_columns(energy));
    std::string w;
    int n = 0;
    while (words >> w) n++;
    EXPECT_EQ(n, kEventRecord + (energy ? kEventLineEnergy : 0));
  }
  EXPECT_EQ(kEventRecord, 11);
  EXPECT_LE(kEventEnergy, kEventLineEnergy);
}
