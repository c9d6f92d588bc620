// Shapes and sizes of the 39 APC 2016 objects, roughly as sold, and the pairs
// a segmenter trained on them tends to confuse.
#include <stdexcept>
#include <string>

#include "synth_internal.hpp"

namespace lom::synth {

namespace {

using R = Rest;
constexpr SynthShape kBox = SynthShape::Box;
constexpr SynthShape kCyl = SynthShape::Cylinder;

CatalogueItem box(double a, double b, double c, std::vector<Rest> rests) {
  return {kBox, Eigen::Vector3d(a, b, c), std::move(rests)};
}
CatalogueItem cylinder(double diameter, double height, std::vector<Rest> rests) {
  return {kCyl, Eigen::Vector3d(diameter, diameter, height), std::move(rests)};
}

const std::vector<CatalogueItem>& catalogue() {
  static const std::vector<CatalogueItem> items = {
      {},                                              // 0 background
      box(0.20, 0.12, 0.05, {R::Flat, R::Side}),       // barkely_hide_bones
      box(0.24, 0.18, 0.05, {R::Flat}),                // cherokee_easy_tee_shirt
      box(0.23, 0.08, 0.06, {R::Flat, R::Side}),       // clorox_utility_brush
      box(0.18, 0.15, 0.12, {R::Flat, R::Side}),       // cloud_b_plush_bear
      box(0.19, 0.12, 0.04, {R::Flat, R::Upright}),    // command_hooks
      box(0.16, 0.09, 0.03, {R::Flat, R::Side}),       // cool_shot_glue_sticks
      box(0.13, 0.10, 0.03, {R::Flat, R::Upright}),    // crayola_24_ct
      box(0.20, 0.13, 0.04, {R::Flat, R::Upright}),    // creativity_chenille_stems
      cylinder(0.066, 0.21, {R::Standing, R::Lying}),  // dasani_water_bottle
      box(0.10, 0.07, 0.04, {R::Flat, R::Side}),       // dove_beauty_bar
      box(0.24, 0.06, 0.04, {R::Flat}),                // dr_browns_bottle_brush
      cylinder(0.08, 0.14, {R::Standing}),             // easter_turtle_sippy_cup
      cylinder(0.05, 0.14, {R::Standing, R::Lying}),   // elmers_washable_no_run_school_glue
      box(0.13, 0.05, 0.035, {R::Flat, R::Side}),      // expo_dry_erase_board_eraser
      box(0.21, 0.09, 0.015, {R::Flat}),               // fiskars_scissors_red
      cylinder(0.07, 0.15, {R::Lying}),                // fitness_gear_3lb_dumbbell
      cylinder(0.10, 0.15, {R::Standing}),             // folgers_classic_roast_coffee
      box(0.24, 0.14, 0.06, {R::Flat}),                // hanes_tube_socks
      box(0.21, 0.16, 0.02, {R::Flat, R::Upright}),    // i_am_a_bunny_book
      box(0.19, 0.135, 0.015, {R::Flat, R::Upright}),  // jane_eyre_dvd
      box(0.22, 0.11, 0.12, {R::Flat}),                // kleenex_paper_towels
      box(0.13, 0.12, 0.12, {R::Flat}),                // kleenex_tissue_box
      box(0.16, 0.12, 0.09, {R::Flat, R::Side}),       // kyjen_squeakin_eggs_plush_puppies
      box(0.18, 0.11, 0.015, {R::Flat, R::Upright}),   // laugh_out_loud_joke_book
      box(0.24, 0.06, 0.025, {R::Flat, R::Side}),      // oral_b_toothbrush_green
      box(0.24, 0.06, 0.025, {R::Flat, R::Side}),      // oral_b_toothbrush_red
      box(0.24, 0.19, 0.04, {R::Flat, R::Upright}),    // peva_shower_curtain_liner
      cylinder(0.18, 0.05, {R::Standing}),             // platinum_pets_dog_bowl
      cylinder(0.074, 0.074, {R::Standing}),           // rawlings_baseball
      cylinder(0.10, 0.14, {R::Standing}),             // rolodex_jumbo_pencil_cup
      box(0.14, 0.08, 0.03, {R::Flat, R::Side}),       // safety_first_outlet_plugs
      box(0.24, 0.16, 0.01, {R::Flat}),                // scotch_bubble_mailer
      cylinder(0.10, 0.05, {R::Standing, R::Lying}),   // scotch_duct_tape
      box(0.12, 0.065, 0.065, {R::Flat, R::Upright}),  // soft_white_lightbulb
      box(0.13, 0.08, 0.025, {R::Flat, R::Side}),      // staples_index_cards
      box(0.19, 0.06, 0.012, {R::Flat}),               // ticonderoga_12_pencils
      cylinder(0.08, 0.13, {R::Standing, R::Lying}),   // up_glucose_bottle
      box(0.24, 0.10, 0.03, {R::Flat}),                // womens_knit_gloves
      cylinder(0.14, 0.05, {R::Standing}),             // woods_extension_cord
  };
  return items;
}

// Pairs of similar packaging or shape; the relation is symmetric.
constexpr int kLookAlikePairs[][2] = {
    {25, 26},  // the two toothbrushes
    {19, 24},  // the two books
    {21, 22},  // the two Kleenex packs
    {6, 13},   // glue sticks and school glue
    {9, 37},   // the two bottles
    {4, 23},   // the two plush toys
    {12, 30},  // sippy cup and pencil cup
    {7, 36},   // crayons and pencils
    {18, 38},  // socks and gloves
    {20, 35},  // dvd and index cards
};

}  // namespace

const CatalogueItem& catalogueItem(int label) {
  if (label < 1 || label > kSynthMaxObjects)
    throw std::out_of_range("no synthetic object for label " + std::to_string(label));
  return catalogue()[static_cast<size_t>(label)];
}

std::vector<int> lookAlikesOf(int label) {
  std::vector<int> result;
  for (const auto& pair : kLookAlikePairs) {
    if (pair[0] == label) result.push_back(pair[1]);
    if (pair[1] == label) result.push_back(pair[0]);
  }
  return result;
}

}  // namespace lom::synth
