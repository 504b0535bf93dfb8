// A cable in sections (issue 22): what each segment is made of, and the clear refusal of a description that
// does not fit the cable.
#include <gtest/gtest.h>

#include <cmath>

#include "rov_tether/core/cable_sections.hpp"

namespace rov_tether
{
namespace
{

TetherParams tenMetres()
{
  TetherParams params;
  params.cable_length = 10.0;
  params.segment_length = 0.1;
  return params;
}

/// Without sections the cable is one section of the tether's own material, every segment of it.
TEST(CableSections, AUniformTetherIsOneSectionOfItsOwnMaterial)
{
  const TetherParams params = tenMetres();
  CableSections sections;
  ASSERT_TRUE(CableSections::make(params, {}, &sections).ok);
  EXPECT_TRUE(sections.uniform());
  ASSERT_EQ(sections.ends().size(), 1u);
  EXPECT_EQ(sections.ends()[0], 100u);
  EXPECT_EQ(sections.materials()[0].axial_stiffness, params.axial_stiffness);
  EXPECT_EQ(sections.materials()[0].mass_per_length, params.mass_per_length);
  EXPECT_EQ(sections.sectionOf(0), 0u);
  EXPECT_EQ(sections.sectionOf(99), 0u);
}

/// Sections in material order from the vehicle end: segment k (from the vehicle) is in the section whose
/// cumulative length first exceeds k segment lengths; unset properties are the tether's; the last section
/// runs to the drum when its length is left out.
TEST(CableSections, SegmentsTakeTheirSectionsMaterialFromTheVehicleEnd)
{
  const TetherParams params = tenMetres();
  CableSection near;  // 2 m of buoyant tether at the vehicle
  near.length = 2.0;
  near.properties = {{"weight_in_water", -0.3}, {"diameter", 0.03}};
  CableSection middle;  // 3 m of stiffer cable
  middle.length = 3.0;
  middle.properties = {{"axial_stiffness", 4e5}};
  CableSection rest;  // to the drum
  CableSections sections;
  const Status made = CableSections::make(params, {near, middle, rest}, &sections);
  ASSERT_TRUE(made.ok) << made.message;
  EXPECT_FALSE(sections.uniform());
  ASSERT_EQ(sections.ends(), (std::vector<std::size_t>{20, 50, 100}));
  EXPECT_EQ(sections.sectionOf(0), 0u);
  EXPECT_EQ(sections.sectionOf(19), 0u);
  EXPECT_EQ(sections.sectionOf(20), 1u);
  EXPECT_EQ(sections.sectionOf(49), 1u);
  EXPECT_EQ(sections.sectionOf(50), 2u);
  EXPECT_EQ(sections.sectionOf(99), 2u);
  const auto& m = sections.materials();
  EXPECT_EQ(m[0].weight_in_water, -0.3);
  EXPECT_EQ(m[0].diameter, 0.03);
  EXPECT_EQ(m[0].axial_stiffness, params.axial_stiffness);
  EXPECT_EQ(m[1].axial_stiffness, 4e5);
  EXPECT_EQ(m[1].weight_in_water, params.weight_in_water);
  EXPECT_EQ(m[2], SectionMaterial::of(params));
}

/// Neighbouring sections of one material are one section (so uniform() tells a solver it may take the
/// tether's own parameters).
TEST(CableSections, SectionsOfOneMaterialMerge)
{
  const TetherParams params = tenMetres();
  CableSection a;
  a.length = 4.0;
  a.properties = {{"mass_per_length", params.mass_per_length}};
  CableSection b;
  CableSections sections;
  ASSERT_TRUE(CableSections::make(params, {a, b}, &sections).ok);
  EXPECT_TRUE(sections.uniform());
  EXPECT_EQ(sections.ends(), (std::vector<std::size_t>{100}));
}

/// A short last segment (cable_length not a multiple of segment_length) belongs to the last section.
TEST(CableSections, TheLastSectionTakesAShortLastSegment)
{
  TetherParams params = tenMetres();
  params.cable_length = 10.05;  // 101 segments, the last 0.05 m
  CableSection a;
  a.length = 5.0;
  a.properties = {{"axial_stiffness", 2e5}};
  CableSection b;
  b.length = 5.05;
  CableSections sections;
  const Status made = CableSections::make(params, {a, b}, &sections);
  ASSERT_TRUE(made.ok) << made.message;
  EXPECT_EQ(sections.ends(), (std::vector<std::size_t>{50, 101}));
}

/// Every way a description does not fit is refused, all of them named in one message, and the output is
/// left as it was.
TEST(CableSections, ADescriptionThatDoesNotFitIsRefusedWithEveryReason)
{
  const TetherParams params = tenMetres();
  CableSections sections;
  ASSERT_TRUE(CableSections::make(params, {}, &sections).ok);
  const auto refused = [&](const std::vector<CableSection>& list, const std::string& reason)
  {
    const Status made = CableSections::make(params, list, &sections);
    EXPECT_FALSE(made.ok) << reason;
    EXPECT_NE(made.message.find(reason), std::string::npos) << made.message;
    EXPECT_TRUE(sections.uniform());  // unchanged
  };
  CableSection straddles;
  straddles.length = 2.05;
  refused({straddles, CableSection{}}, "not a whole number of segments");
  CableSection sliver;  // rounds to no segment at all: its material would be nowhere
  sliver.length = 1e-9;
  refused({sliver, CableSection{}}, "not a whole number of segments");
  // A length left out before the last is a missing key, said as one (it read "must be finite and positive (got
  // nan)"), and what the sections add up to is not said of lengths that are not all known (it said 3 m of 10 m).
  CableSection missing;
  CableSection three;
  three.length = 3.0;
  refused({missing, three},
          "sections: section 1 of 2: length: missing (only the last section may leave it out: it runs to the drum)");
  const Status left_out = CableSections::make(params, {missing, three}, &sections);
  EXPECT_EQ(left_out.message.find("nan"), std::string::npos) << left_out.message;
  EXPECT_EQ(left_out.message.find("add up"), std::string::npos) << left_out.message;
  EXPECT_EQ(CableSections::make(params, {missing, missing, CableSection{}}, &sections).message,
            "sections: section 1 of 3: length: missing (only the last section may leave it out: it runs to the drum); "
            "section 2 of 3: length: missing (only the last section may leave it out: it runs to the drum)");
  // A length given but unusable is a bad value, named with its value.
  CableSection negative;
  negative.length = -1.0;
  refused({negative, CableSection{}}, "sections: section 1 of 2: length = -1 m: must be finite and > 0");
  CableSection zero;
  zero.length = 0.0;
  refused({zero, three}, "sections: section 1 of 2: length = 0 m: must be finite and > 0");
  const Status bad_value = CableSections::make(params, {zero, three}, &sections);
  EXPECT_EQ(bad_value.message.find("leave"), std::string::npos) << "no word of leaving it out: " << bad_value.message;
  EXPECT_EQ(bad_value.message.find("add up"), std::string::npos) << bad_value.message;
  CableSection too_long;
  too_long.length = 12.0;
  refused({too_long, CableSection{}}, "beyond the cable's");
  CableSection short_total;
  short_total.length = 3.0;
  CableSection short_last = short_total;
  refused({short_total, short_last}, "sections: their lengths add up to 6 m, not cable_length 10 m");
  CableSection unknown;
  unknown.length = 2.0;
  unknown.properties = {{"winch_speed", 1.0}};
  refused({unknown, CableSection{}}, "'winch_speed' is not a property a section may set");
  CableSection twice;
  twice.length = 2.0;
  twice.properties = {{"diameter", 0.02}, {"diameter", 0.03}};
  refused({twice, CableSection{}}, "'diameter' is set twice");
  CableSection out_of_range;
  out_of_range.length = 2.0;
  out_of_range.properties = {{"axial_stiffness", -5.0}};
  refused({out_of_range, CableSection{}}, "section 1 of 2: axial_stiffness");
  CableSection nan_value;
  nan_value.length = 2.0;
  nan_value.properties = {{"mass_per_length", std::nan("")}};
  refused({nan_value, CableSection{}}, "section 1 of 2: mass_per_length");
  // Two faults at once: both named.
  const Status both = CableSections::make(params, {straddles, unknown, CableSection{}}, &sections);
  EXPECT_NE(both.message.find("section 1 of 3"), std::string::npos) << both.message;
  EXPECT_NE(both.message.find("section 2 of 3"), std::string::npos) << both.message;
}

// Every error of every section is said in one message, whatever is wrong with a length: a section whose length is
// missing still has its properties checked, and so has the last section when what the ones before it cover is not
// known. Here section 1 misses its length and sets a property a section may not set, section 2 sets a negative
// diameter, and the last (left to run to the drum) a negative EA: four errors. Before, a missing length ended the
// section's checks, and the last section's too (only the first and the second's diameter were said).
TEST(CableSections, EveryErrorOfEverySectionIsSaidInOneMessage)
{
  const TetherParams params = tenMetres();
  CableSection missing;
  missing.properties = {{"winch_speed", 1.0}};
  CableSection second;
  second.length = 3.0;
  second.properties = {{"diameter", -1.0}};
  CableSection last;
  last.properties = {{"axial_stiffness", -5.0}};
  CableSections sections;
  const Status made = CableSections::make(params, {missing, second, last}, &sections);
  EXPECT_FALSE(made.ok);
  for (const char* error :
       {"section 1 of 3: length: missing", "section 1 of 3: 'winch_speed' is not a property a section may set",
        "section 2 of 3: diameter = -1", "section 3 of 3: axial_stiffness = -5"})
  {
    EXPECT_NE(made.message.find(error), std::string::npos) << error << " in: " << made.message;
  }
  EXPECT_TRUE(sections.uniform());  // unchanged
}

}  // namespace
}  // namespace rov_tether
