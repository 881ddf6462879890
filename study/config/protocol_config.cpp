#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/number_text.h"
#include "core/toml_fields.h"
#include "study/config/config_reading.h"
#include "study/config/input_keys.h"
#include "study/config/study_config.h"

namespace fovlab::config_detail {
namespace {

ProtocolKind read_kind(const TomlFields& fields) {
  const std::string kind = fields.string("kind");
  const std::optional<ProtocolKind> found = find_protocol(kind);
  if (!found) fields.fail("kind", "expected one of " + known_protocols() + ", got \"" + kind + "\"");
  return *found;
}

// A rule's error "KEY: expected ..." as a config error of the procedure's table.
// ("levels: ..." is about [levels], not a key of the procedure's table.)
[[noreturn]] void fail_with_rule_error(const TomlFields& fields, const std::string& error, const std::string& suffix) {
  const size_t colon = error.find(": ");
  const std::string key = error.substr(0, colon);
  if (key == "levels") fields.fail("", "[levels] values: " + error.substr(colon + 2) + suffix);
  fields.fail(key, error.substr(colon + 2) + suffix);
}

}  // namespace

void read_protocol(const TomlFields& fields, const LevelsConfig& levels, const StimulusConfig& stimulus,
                   ProtocolConfig& protocol) {
  protocol.kind = read_kind(fields);
  const bool ladder = protocol.kind == ProtocolKind::ramp || protocol.kind == ProtocolKind::slider;
  if (ladder && levels.values.size() < 2)
    fields.fail("kind", std::string(protocol_name(protocol.kind)) + " needs a [levels] table with at least two values");
  for (const VariantConfig& variant : stimulus.variants)
    if (ladder && variant_levels(levels, &variant).size() < 2)
      fields.fail("kind", std::string(protocol_name(protocol.kind)) +
                              " needs at least two levels in every variant (\"" + variant.name +
                              "\" has fewer in the conditions file)");
  if (protocol.kind == ProtocolKind::two_afc) {
    const std::string question = fields.string("question");
    const std::optional<TwoAfcQuestion> found = find_two_afc_question(question);
    if (!found)
      fields.fail("question",
                  "expected \"same\" (same/different) or \"better\" (first/second), got \"" + question + "\"");
    protocol.two_afc_question = *found;
  }
  protocol.repeats = bounded_integer(fields, "repeats", 1, 1, 1000);
  const ProtocolRules& rules = protocol.rules();
  const bool two_intervals = rules.two_intervals;
  // Default: counterbalanced whenever the repeats can be split in halves.
  protocol.counterbalance = fields.boolean("counterbalance", two_intervals && protocol.repeats % 2 == 0);
  if (protocol.counterbalance && !two_intervals)
    fields.fail("counterbalance", "only 2afc, pair and rating trials have an order to counterbalance");
  if (protocol.counterbalance && protocol.repeats % 2 != 0)
    fields.fail("repeats", "expected an even number with counterbalance = true (half with the reference first)");
  const std::string trial_order = fields.string("trial_order", "random");
  if (trial_order != "random" && trial_order != "fixed") fields.fail("trial_order", "expected \"random\" or \"fixed\"");
  protocol.randomise_trials = trial_order == "random";
  const std::string block_order = fields.string("block_order", "fixed");
  if (block_order == "fixed") protocol.block_order = ProtocolConfig::BlockOrder::fixed;
  else if (block_order == "random") protocol.block_order = ProtocolConfig::BlockOrder::random;
  else if (block_order == "latin_square") protocol.block_order = ProtocolConfig::BlockOrder::latin_square;
  else fields.fail("block_order", "expected \"fixed\", \"random\" or \"latin_square\"");
  protocol.question.text = fields.string("question_text", std::string(rules.default_question));

  const toml::table* keys_table = fields.optional_table("keys");
  std::map<std::string, std::string> answer_of_key;
  for (const ProtocolAnswer& rule : rules.answers) {
    const std::string answer(rule.name);
    std::vector<std::string> keys(rule.default_keys.begin(), rule.default_keys.end());
    if (keys_table) {
      const TomlFields keys_fields(*keys_table, fields.path(), fields.name_of("keys"));
      if (keys_fields.has(answer)) {
        keys = keys_fields.strings(answer);
        for (const std::string& key : keys)
          if (!is_input_name(key))
            keys_fields.fail(answer, "unknown key \"" + key + "\" (expected one of " + input_names_summary() + ")");
      }
    }
    for (const std::string& key : keys) {
      const auto [where, inserted] = answer_of_key.emplace(key, answer);
      if (!inserted)
        fields.fail("keys", "key \"" + key + "\" is bound to both \"" + where->second + "\" and \"" + answer + "\"");
    }
    protocol.question.answers.emplace_back(answer, std::move(keys));
  }
  if (keys_table) {
    const TomlFields keys_fields(*keys_table, fields.path(), fields.name_of("keys"));
    for (auto&& [key, node] : *keys_table)
      if (!rules.is_answer(key.str())) {
        std::string expected;
        for (const ProtocolAnswer& answer : rules.answers)
          expected += (expected.empty() ? "" : ", ") + std::string(answer.name);
        keys_fields.fail(std::string(key.str()), "not an answer of this protocol (expected " + expected + ")");
      }
  }
  if (protocol.kind == ProtocolKind::slider) {
    protocol.slider.start_level = fields.number("start_level", levels.values.empty() ? 0.0 : levels.values.front());
    if (std::find(levels.values.begin(), levels.values.end(), protocol.slider.start_level) == levels.values.end())
      fields.fail("start_level", "expected one of [levels] values");
    for (const VariantConfig& variant : stimulus.variants) {
      const std::vector<double>& own = variant_levels(levels, &variant);
      if (std::find(own.begin(), own.end(), protocol.slider.start_level) == own.end())
        fields.fail("start_level", "expected a level of every variant (\"" + variant.name + "\" has no " +
                                       format_number(protocol.slider.start_level, 6) + " in the conditions file)");
    }
  }
  fields.finish();
}

void read_timing(const TomlFields& fields, TimingConfig& timing) {
  timing.black_interval_s = bounded_number(fields, "black_interval_s", timing.black_interval_s, 0.0, 600.0);
  timing.inter_trial_s = bounded_number(fields, "inter_trial_s", timing.inter_trial_s, 0.0, 600.0);
  timing.rest_between_blocks_s =
      bounded_number(fields, "rest_between_blocks_s", timing.rest_between_blocks_s, 0.0, 7200.0);
  timing.response_timeout_s = bounded_number(fields, "response_timeout_s", timing.response_timeout_s, 0.0, 3600.0);
  timing.fixation_s = bounded_number(fields, "fixation_s", timing.fixation_s, 0.0, 60.0);
  fields.finish();
}

void read_attention(const TomlFields& fields, const ProtocolConfig& protocol, AttentionConfig& attention) {
  attention.share = fields.number("share");
  check_range(fields, "share", attention.share, 0.0, 0.9);
  if (attention.share > 0 && identical_answer(protocol).empty())
    fields.fail("share",
                "attention checks need an answer that means \"identical\" (2afc with question = \"same\", "
                "pair or rating)");
  attention.break_s = bounded_number(fields, "break_s", attention.break_s, 0.0, 3600.0);
  attention.max_errors = bounded_integer(fields, "max_errors", attention.max_errors, 1, 1000);
  attention.excluded_message = fields.string("excluded_message", attention.excluded_message);
  fields.finish();
}

void read_practice(const TomlFields& fields, StudyConfig& config, const Reading& reading, SceneKind scene_kind) {
  PracticeConfig& practice = config.practice;
  practice.trials = bounded_integer(fields, "trials", std::nullopt, 0, 1000);
  const bool comparison = config.protocol.kind != ProtocolKind::ramp && config.protocol.kind != ProtocolKind::slider;
  if (fields.has("levels")) {
    if (!comparison)
      fields.fail("levels", std::string("a ") + protocol_name(config.protocol.kind) +
                                " practice trial shows the whole ladder of levels; expected no practice.levels");
    practice.levels = fields.numbers("levels");
    for (double level : practice.levels)
      if (std::find(config.levels.values.begin(), config.levels.values.end(), level) == config.levels.values.end())
        fields.fail("levels", "expected levels of [levels] values, got " + format_number(level, 6));
  } else if (comparison && !config.levels.values.empty()) {
    // The level least like the reference: the easiest difference to see.
    practice.levels = {config.levels.higher_is_better ? config.levels.values.front() : config.levels.values.back()};
  }
  if (fields.has("scene"))
    practice.scene = resolve_scene(fields, fields.string("scene"), config.source_path, reading.scenes, scene_kind);
  fields.finish();
}

// [procedure.NAME]: read here; checked against each variant's levels when a block names it.
ProcedureConfig read_procedure(const TomlFields& fields, const std::string& name) {
  ProcedureConfig procedure;
  procedure.name = name;
  if (!is_safe_name(name)) fields.fail("", "expected a procedure name of letters, digits, '_', '-' or '.'");
  StaircaseRule& rule = procedure.staircase;
  const std::string kind = fields.string("kind");
  if (kind == "staircase") {
    rule.kind = StaircaseRule::Kind::transformed;
    rule.down = bounded_integer(fields, "down", 2, 1, 10);
    rule.step_sizes.clear();
    for (double step : fields.has("step_sizes") ? fields.numbers("step_sizes") : std::vector<double>{1.0}) {
      if (!(step >= 1 && step <= 1000 && step == std::floor(step)))
        fields.fail("step_sizes", "expected whole numbers of grid steps, 1 or more, got " + format_number(step, 6));
      rule.step_sizes.push_back(static_cast<int>(step));
    }
  } else if (kind == "weighted") {
    rule.kind = StaircaseRule::Kind::weighted;
    rule.harder_steps = bounded_integer(fields, "harder_steps", 1, 1, 1000);
    rule.easier_steps = bounded_integer(fields, "easier_steps", 3, 1, 1000);
  } else if (kind == "quest_plus") {
    procedure.kind = ProcedureConfig::Kind::quest_plus;
    QuestPlusRule& quest = procedure.quest;
    const std::string shape = fields.string("shape", "logistic");
    if (shape == "logistic") quest.shape = PsychometricShape::logistic;
    else if (shape == "weibull") quest.shape = PsychometricShape::weibull;
    else if (shape == "cumulative_normal") quest.shape = PsychometricShape::cumulative_normal;
    else fields.fail("shape", "expected \"logistic\", \"weibull\" or \"cumulative_normal\", got \"" + shape + "\"");
    for (const auto& [key, grid] : {std::pair{"thresholds", &quest.thresholds}, std::pair{"slopes", &quest.slopes},
                                    std::pair{"lapses", &quest.lapses}})
      if (fields.has(key)) *grid = fields.numbers(key);
    // Not given: -1, the protocol's (quest_plus_rule).
    quest.guess = fields.has("guess_rate") ? bounded_number(fields, "guess_rate", 0.0, 0.0, 0.99) : -1.0;
    quest.prior_mean = fields.number("prior_mean", 0.0);
    quest.prior_sd = bounded_number(fields, "prior_sd", 0.0, 0.0, 1e300);
    if (fields.has("prior_mean") != fields.has("prior_sd"))
      fields.fail(fields.has("prior_mean") ? "prior_mean" : "prior_sd",
                  std::string("expected ") + (fields.has("prior_mean") ? "prior_sd" : "prior_mean") +
                      " too (a normal prior over thresholds; without both the prior is uniform)");
    quest.max_trials = bounded_integer(fields, "max_trials", std::nullopt, 1, 10000);
    quest.stop_entropy_bits = bounded_number(fields, "stop_entropy_bits", 0.0, 0.0, 1000.0);
    quest.stop_interval_width = bounded_number(fields, "stop_interval_width", 0.0, 0.0, 1e300);
    return procedure;
  } else {
    fields.fail("kind",
                "expected \"staircase\" (Levitt's transformed up-down), \"weighted\" (Kaernbach's weighted "
                "up-down) or \"quest_plus\" (Watson's QUEST+), got \"" +
                    kind + "\"");
  }
  rule.max_trials = bounded_integer(fields, "max_trials", std::nullopt, 1, 10000);
  rule.max_reversals = bounded_integer(fields, "max_reversals", 0, 0, 10000);
  rule.reversals_averaged = bounded_integer(fields, "reversals_averaged", 6, 1, 10000);
  if (fields.has("starts")) procedure.starts = fields.numbers("starts");
  if (procedure.starts.size() > 16) fields.fail("starts", "expected at most 16 interleaved staircases");
  return procedure;
}

// The QUEST+ tables a session would hold: one per (procedure, variant) that a block uses, at most
// kQuestPlusMaxTableEntries entries in all.
void check_quest_plus_tables(const TomlFields& fields, const StudyConfig& config) {
  std::set<int> used;
  for (const BlockConfig& block : config.blocks)
    if (block.procedure >= 0 && config.procedures[size_t(block.procedure)].kind == ProcedureConfig::Kind::quest_plus)
      used.insert(block.procedure);
  const std::vector<const VariantConfig*> variants = tested_variants(config.stimulus);
  size_t entries = 0;
  for (int index : used)
    for (const VariantConfig* variant : variants) {
      const std::vector<double> grid = adaptive_grid(config.levels, variant);
      const QuestPlusRule rule =
          quest_plus_rule(config.procedures[size_t(index)], config.protocol, config.levels, grid);
      entries += grid.size() * rule.thresholds.size() * rule.slopes.size() * rule.lapses.size();
    }
  if (entries > kQuestPlusMaxTableEntries)
    fields.table("procedure")
        .table(config.procedures[size_t(*used.rbegin())].name)
        .fail("thresholds", "the QUEST+ tables of every variant and procedure would hold " + std::to_string(entries) +
                                " entries (levels x grid points); expected at most " +
                                std::to_string(kQuestPlusMaxTableEntries) + ": fewer levels, grid points or variants");
}

// A block's procedure against the study: a protocol whose answers are right or wrong, and a rule
// that works on every variant's level grid (a staircase from every start).
void check_procedure(const TomlFields& fields, const StudyConfig& config, const ProcedureConfig& procedure) {
  const ProtocolKind kind = config.protocol.kind;
  if (kind != ProtocolKind::two_afc && kind != ProtocolKind::pair)
    fields.fail("", std::string("an adaptive procedure needs answers that see the difference or not (2afc, pair); the "
                                "protocol is ") +
                        protocol_name(kind));
  const std::vector<const VariantConfig*> variants = tested_variants(config.stimulus);
  for (const VariantConfig* variant : variants) {
    const std::vector<double> grid = adaptive_grid(config.levels, variant);
    const std::string of_variant = variant ? " (variant \"" + variant->name + "\")" : "";
    if (procedure.kind == ProcedureConfig::Kind::quest_plus) {
      const QuestPlusRule rule = quest_plus_rule(procedure, config.protocol, config.levels, grid);
      if (const std::optional<std::string> error = quest_plus_rule_error(rule, grid))
        fail_with_rule_error(fields, *error, of_variant);
      continue;
    }
    std::vector<int> start_indices;
    for (double start : procedure.starts) {
      const auto found = std::find(grid.begin(), grid.end(), start);
      if (found == grid.end())
        fields.fail("starts", "expected levels of the grid" + of_variant + ", got " + format_number(start, 6));
      start_indices.push_back(static_cast<int>(found - grid.begin()));
    }
    if (start_indices.empty()) start_indices.push_back(0);
    for (int start : start_indices) {
      StaircaseRule rule = procedure.staircase;
      rule.start_index = start;
      if (const std::optional<std::string> error = staircase_rule_error(rule, static_cast<int>(grid.size())))
        fail_with_rule_error(fields, *error, of_variant);
    }
  }
}

}  // namespace fovlab::config_detail

namespace fovlab {

std::vector<std::string> protocol_answers(ProtocolKind kind, TwoAfcQuestion question) {
  std::vector<std::string> names;
  for (const ProtocolAnswer& answer : protocol_rules(kind, question).answers) names.emplace_back(answer.name);
  return names;
}

std::string identical_answer(const ProtocolConfig& protocol) { return std::string(protocol.rules().identical); }

std::vector<double> adaptive_grid(const LevelsConfig& levels, const VariantConfig* variant) {
  const std::vector<double>& grid = variant_levels(levels, variant);
  if (levels.higher_is_better) return grid;
  return {grid.rbegin(), grid.rend()};
}

QuestPlusRule quest_plus_rule(const ProcedureConfig& procedure, const ProtocolConfig& protocol,
                              const LevelsConfig& levels, const std::vector<double>& grid) {
  QuestPlusRule rule = procedure.quest;
  // Higher levels more like the reference: the difference is seen less as the level grows.
  rule.rising = !levels.higher_is_better;
  if (rule.guess < 0)
    rule.guess =
        protocol.kind == ProtocolKind::two_afc && protocol.two_afc_question == TwoAfcQuestion::better ? 0.5 : 0.05;
  if (grid.size() < 2) return rule;
  if (rule.thresholds.empty()) rule.thresholds = default_quest_thresholds(grid, rule.shape);
  if (rule.slopes.empty()) rule.slopes = default_quest_slopes(grid, rule.shape);
  if (rule.lapses.empty()) rule.lapses = default_quest_lapses();
  return rule;
}

}  // namespace fovlab
