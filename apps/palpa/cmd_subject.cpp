// SPDX-License-Identifier: AGPL-3.0-or-later
// palpa subject check / plan / dataset / body: the steps of a subject's
// pipeline that are the subject's own (the others are palpa acquire, fit,
// rest and design), called by the workflow (workflow/Snakefile).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <array>

#include "cli_common.hpp"
#include "commands.hpp"
#include "palpa/core/atomic_file.hpp"
#include "palpa/core/units.hpp"
#include "palpa/pipeline/body_fields.hpp"
#include "palpa/pipeline/cohort_design.hpp"
#include "palpa/pipeline/report.hpp"
#include "palpa/pipeline/subject.hpp"

namespace palpa::cli {

namespace {

namespace fs = std::filesystem;

void check(const std::string& file) {
  const pipeline::Subject s = pipeline::read_subject(file);
  pipeline::check_locations_on_body(s);
  std::size_t pokes = 0, ultrasound = 0;
  for (const pipeline::Location& l : s.locations) {
    pokes += l.pokes.size();
    ultrasound += l.ultrasound ? 1 : 0;
  }
  fmt::print(
      "subject {}: {} locations on the body, {} pokes, {} with ultrasound depths, {} searched; "
      "design {}{}\n",
      s.name, s.locations.size(), pokes, ultrasound, s.locations.size() - ultrasound,
      s.design.string(), s.pressure ? "; measured pressure map to compare" : "");
}

void plan(const std::string& file, const std::string& output) {
  const Json p = pipeline::cohort_plan(pipeline::read_subjects(file));
  if (output.empty()) {
    fmt::print("{}\n", p.dump(2));
  } else {
    write_file_atomic(output, [&](std::ostream& o) { o << format_json(p, output); });
  }
}

// The cohort's design scene: one support for every subject's body.
void cohort(const std::string& file, const std::string& results, const std::string& output) {
  const std::vector<pipeline::Subject> subjects = pipeline::read_subjects(file);
  const Json scene = pipeline::cohort_design_scene(subjects, results);
  const fs::path out(output);
  if (out.has_parent_path()) ensure_directory(out.parent_path());
  write_file_atomic(out, [&](std::ostream& o) { o << format_json(scene, out); });
  spdlog::info("cohort {}: one support for {} bodies; wrote {} (run it with palpa design)", file, subjects.size(),
               output);
}

struct DatasetArgs {
  std::string subject, location, curves, ultrasound, output;
};

void dataset(const DatasetArgs& a) {
  const pipeline::Subject s = pipeline::read_subject(a.subject);
  const fs::path out(a.output);
  const fs::path folder = out.has_parent_path() ? out.parent_path() : fs::path(".");
  ensure_directory(folder);
  const Json d = pipeline::location_dataset(
      s, a.location, a.curves,
      a.ultrasound.empty() ? std::nullopt : std::optional<fs::path>(a.ultrasound), folder);
  write_file_atomic(out, [&](std::ostream& o) { o << format_json(d, out); });
  spdlog::info("subject {}, location {}: dataset of {} curves, layer depth {}; wrote {}", s.name,
               a.location, d.at("curves").size(), d.at("layer_depth").dump(), a.output);
}

void body(const std::string& subject, const std::string& fits, const std::string& output, bool overwrite) {
  if (!overwrite) require_empty_output(output);
  const pipeline::Subject s = pipeline::read_subject(subject);
  const pipeline::BodyFields f = pipeline::read_location_fits(s, fits);
  pipeline::write_body_fields(s, f, output);
  for (const pipeline::LocationFit& l : f.fits) {
    spdlog::info("{}: E {}, ν {:.3f}, depth {} ({}), relative error {:.3g}", l.name,
                 format_quantity(l.young, Dimension::Pressure), l.poisson,
                 format_quantity(l.depth, Dimension::Length),
                 l.depth_searched ? "searched" : "measured", l.relative_error);
  }
  spdlog::info("subject {}: the body carries {} fits, the shape of {}; wrote {}", s.name,
               f.fits.size(), f.fits[f.shape].name, output);
}

void report_command(const std::string& subject, const std::string& results, const std::string& output) {
  const pipeline::Subject s = pipeline::read_subject(subject);
  pipeline::subject_report(s, results).write(output);
  spdlog::info("subject {}: report written to {}", s.name, output);
}

}  // namespace

void add_subject_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "subject",
      "A subject's own pipeline steps (the workflow in workflow/Snakefile calls them): check "
      "a subject file, plan its jobs, write a location's fit dataset, make the body "
      "carry the fits.");
  cmd->require_subcommand(1);

  auto* check_cmd =
      cmd->add_subcommand("check",
                          "Check a subject file: every key, file and name, and that every "
                          "location lies on the body.\n  palpa subject check subject.json");
  auto check_file = std::make_shared<std::string>();
  check_cmd->add_option("subject", *check_file, "Subject file (JSON)")->required();
  declare_paths(*check_cmd, {"subject"}, {});
  check_cmd->callback([check_file] { check(*check_file); });

  auto* plan_cmd = cmd->add_subcommand("plan",
                                       "The jobs of a subject's or a cohort's pipelines as JSON "
                                       "(per location its pokes' and ultrasound's "
                                       "inputs and acquisition arguments; the fit's arguments), "
                                       "after checking the files (palpa subject check "
                                       "also checks that the locations lie on the body).\n  palpa "
                                       "subject plan cohort.json -o plan.json");
  auto plan_args = std::make_shared<std::pair<std::string, std::string>>();
  plan_cmd
      ->add_option(
          "subject", plan_args->first,
          "Subject file, or cohort file {\"palpa_cohort\": 1, \"subjects\": [subject files]}")
      ->required();
  plan_cmd->add_option("-o,--output", plan_args->second, "Plan file (default: print it)");
  declare_paths(*plan_cmd, {"subject"}, {"-o"});
  plan_cmd->callback([plan_args] { plan(plan_args->first, plan_args->second); });

  auto* cohort_cmd = cmd->add_subcommand(
      "cohort",
      "The design scene of one support for every subject of a cohort: each subject's body as palpa subject body "
      "wrote it, on the support and design settings of their common template, with each body's own design beside "
      "(run it with palpa design).\n  palpa subject cohort cohort.json --results out -o out/cohort/scene.json");
  auto ca = std::make_shared<std::array<std::string, 3>>();
  cohort_cmd->add_option("cohort", (*ca)[0], "Cohort file {\"palpa_cohort\": 1, \"subjects\": [subject files]}")
      ->required();
  cohort_cmd->add_option("--results", (*ca)[1], "The results folder (one folder per subject, each with body/)")
      ->required();
  cohort_cmd->add_option("-o,--output", (*ca)[2], "The cohort's design scene (JSON)")->required();
  declare_paths(*cohort_cmd, {"cohort"}, {"-o"});
  cohort_cmd->callback([ca] { cohort((*ca)[0], (*ca)[1], (*ca)[2]); });

  auto* ds_cmd = cmd->add_subcommand(
      "dataset",
      "A location's fit dataset: its acquired curves, its layer depth (measured by ultrasound) or "
      "the "
      "depths to search.\n  palpa subject dataset subject.json --location thigh-left --curves "
      "out/curves/thigh-left --ultrasound out/depths/thigh-left.json -o out/fits/thigh-left.json");
  auto ds = std::make_shared<DatasetArgs>();
  ds_cmd->add_option("subject", ds->subject, "Subject file (JSON)")->required();
  ds_cmd->add_option("--location", ds->location, "The location's name")->required();
  ds_cmd
      ->add_option("--curves", ds->curves,
                   "Folder of the location's curves, <tag>.csv per poke (r4mm.csv)")
      ->required();
  ds_cmd->add_option(
      "--ultrasound", ds->ultrasound,
      "The location's ultrasound summary (palpa acquire ultrasound --summary), when it has one");
  ds_cmd->add_option("-o,--output", ds->output, "Dataset file (JSON) to write")->required();
  declare_paths(*ds_cmd, {"subject", "--ultrasound"}, {"-o"});
  ds_cmd->callback([ds] { dataset(*ds); });

  auto* body_cmd =
      cmd->add_subcommand("body",
                          "Make the body carry the fits: depth and modulus samples at the "
                          "locations, the material's common "
                          "shape, and the rest and design scenes of the subject's body.\n"
                          "  palpa subject body subject.json --fits out/fits -o out/body");
  auto ba = std::make_shared<std::array<std::string, 3>>();
  body_cmd->add_option("subject", (*ba)[0], "Subject file (JSON)")->required();
  body_cmd
      ->add_option("--fits", (*ba)[1],
                   "Folder of the fits, one folder per location (palpa fit's output)")
      ->required();
  body_cmd
      ->add_option("-o,--output", (*ba)[2],
                   "Output folder (depths.csv, moduli.csv, material.json, fields.json, rest.json, "
                   "design.json)")
      ->required();
  auto body_overwrite = std::make_shared<bool>(false);
  body_cmd->add_flag("--overwrite", *body_overwrite,
                     "Write into a non-empty output folder (the files palpa wrote there before and does not "
                     "write again are removed)");
  declare_paths(*body_cmd, {"subject"}, {"-o"});
  body_cmd->callback([ba, body_overwrite] { body((*ba)[0], (*ba)[1], (*ba)[2], *body_overwrite); });

  auto* report_cmd = cmd->add_subcommand(
      "report", "The subject's report: one self-contained HTML file of the fits, the body's fields, the body at rest, "
                "the designed support and the measured map, from the results folder.\n"
                "  palpa subject report subject.json --results out/s01 -o out/s01/report.html");
  auto ra = std::make_shared<std::array<std::string, 3>>();
  report_cmd->add_option("subject", (*ra)[0], "Subject file (JSON)")->required();
  report_cmd->add_option("--results", (*ra)[1], "The subject's results folder (fits/, body/, rest/, design/)")
      ->required();
  report_cmd->add_option("-o,--output", (*ra)[2], "Report file (HTML)")->required();
  declare_paths(*report_cmd, {"subject"}, {"-o"});
  report_cmd->callback([ra] { report_command((*ra)[0], (*ra)[1], (*ra)[2]); });
}

}  // namespace palpa::cli
