#include "design/exact_selection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/format.h"
#include "solvers/common/candidates.h"

namespace gyrosid::design {

void ExactSelectionOptions::bind(OptionTable& t) {
  t.integer("select.rounds", &rounds, 0, 5,
            "cof_minimax: rounds of the exact final selection (0: off; each re-solves the proxy, corrected towards the exact predictor, "
            "from the best programme so far, and scores the candidates by the evidence-network prediction)")
      .text("select.emphasis", &emphasis, "exact selection: factors (>= 1) the worst flight's requirement is raised by, one re-solve each")
      .text("select.blend_shares", &blend_shares, "exact selection: budget shares (0..1) of the most emphasised programme in blends with the best");
}

std::vector<double> ExactSelectionOptions::emphasis_factors() const { return parse_list(emphasis, "select.emphasis"); }

std::vector<double> ExactSelectionOptions::shares() const {
  return blend_shares.empty() ? std::vector<double>{} : parse_list(blend_shares, "select.blend_shares");
}

std::string ExactSelectionOptions::validate() const {
  try {
    const std::vector<double> e = emphasis_factors();
    if (e.empty()) return "option 'select.emphasis' needs at least one factor";
    for (double v : e) {
      if (!(v >= 1.0 && v <= 1e3)) return str_cat("option 'select.emphasis': factor ", v, " is not in [1, 1000]");
    }
    for (double s : shares()) {
      if (!(s > 0.0 && s < 1.0)) return str_cat("option 'select.blend_shares': share ", s, " is not in (0, 1)");
    }
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

std::string ExactSelectionOptions::validate(Criterion criterion, bool has_reference) const {
  if (auto p = validate(); !p.empty()) return p;
  if (rounds > 0 && (criterion != Criterion::cof_minimax || !has_reference)) {
    return "option 'select.rounds' (the exact final selection) is for --criterion cof_minimax with a reference";
  }
  return "";
}

std::vector<double> flight_gains(const Prediction& p, const std::vector<double>& reference) {
  if (p.flights.size() != reference.size() || reference.empty()) {
    fail("design: exact selection needs the reference's prediction on the same flights (", reference.size(), " against ", p.flights.size(), ")");
  }
  std::vector<double> g;
  for (std::size_t f = 0; f < reference.size(); ++f) g.push_back(reference[f] / std::max(p.flights[f].cof_m, 1e-300));
  return g;
}

std::size_t best_worst_flight(const std::vector<std::vector<double>>& gains) {
  std::size_t best = 0;
  double best_worst = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < gains.size(); ++i) {
    const double worst = gains[i].empty() ? -std::numeric_limits<double>::infinity() : *std::min_element(gains[i].begin(), gains[i].end());
    if (worst > best_worst) best = i, best_worst = worst;
  }
  return best;
}

TableProfile blend_programmes(const TableProfile& first, const TableProfile& second, double share) {
  if (!(share > 0.0 && share < 1.0)) fail("design: a blend's share must be in (0, 1), got ", share);
  if (first.segments.empty() || second.segments.empty()) fail("design: a blend needs two non-empty programmes");
  const double total = first.duration_s();
  TableProfile out = first;
  out.segments.clear();
  double temp = first.segments.front().chamber_start_c;
  const auto append = [&](const TableProfile& p, double scale) {
    for (const ProfileSegment& s : p.segments) {
      ProfileSegment q = s;
      q.duration_s = s.duration_s * scale;
      q.rate.cycles = s.rate.cycles * scale;  // the same cycle period
      // the chamber goes towards the segment's end temperature no faster than its limits (C/min)
      q.chamber_start_c = temp;
      q.chamber_end_c = out.limits.reach_c(temp, s.chamber_end_c, q.duration_s);
      temp = q.chamber_end_c;
      out.segments.push_back(q);
    }
  };
  append(first, (1.0 - share) * total / first.duration_s());
  append(second, share * total / second.duration_s());
  if (auto p = out.check_limits(); !p.empty()) fail("design: blend: ", p);
  return out;
}

SelectionResult select_by_exact(const DesignProblem& problem, const TableProfile& solved, const ExactSelectionOptions& options,
                                const SolveFrom& solve, const PredictExactly& predict) {
  const DesignContext& context = problem.context();
  if (auto p = options.validate(context.criterion(), !context.reference_cof_m().empty()); !p.empty()) fail("design: ", p);
  const std::vector<double>& reference = context.reference_cof_m();
  SelectionResult r;
  const auto add = [&](std::string name, TableProfile programme, std::vector<double> offsets) {
    for (const SelectionCandidate& c : r.candidates) {
      if (c.programme.segments == programme.segments) {  // already scored
        r.repeats.push_back(str_cat(name, " = ", c.name));
        return;
      }
    }
    SelectionCandidate c;
    c.name = std::move(name);
    c.predicted = predict(programme);
    c.gain = flight_gains(c.predicted, reference);
    c.worst_gain = *std::min_element(c.gain.begin(), c.gain.end());
    DesignProblem plain = problem;
    plain.set_flight_offsets({});
    c.proxy_objective = plain.objective(programme);
    c.programme = std::move(programme);
    c.offsets = std::move(offsets);
    r.candidates.push_back(std::move(c));
  };
  const auto choose = [&] {
    std::vector<std::vector<double>> gains;
    for (const SelectionCandidate& c : r.candidates) gains.push_back(c.gain);
    return best_worst_flight(gains);
  };
  add("solver", solved, {});
  const std::vector<double> emphasis = options.emphasis_factors(), shares = options.shares();
  for (int round = 1; round <= options.rounds; ++round) {
    // The incumbent: the best programme so far that the solver can start from (a blend has more segments).
    std::vector<std::vector<double>> gains;
    for (const SelectionCandidate& c : r.candidates) {
      const bool solvable = c.programme.segments.size() == static_cast<std::size_t>(problem.space().options().segments);
      gains.push_back(solvable ? c.gain : std::vector<double>{});
    }
    const SelectionCandidate incumbent = r.candidates[best_worst_flight(gains)];
    // The correction: the exact predictor's log ratio minus the proxy's, per flight, at the incumbent.
    const std::vector<double> proxy = context.flight_log_ratios(
        context.estimate(problem.observe_programme(incumbent.programme), context.objective_needs_target()));
    const std::vector<double> exact = context.flight_log_ratios(incumbent.predicted);
    std::vector<double> correction;
    for (std::size_t f = 0; f < proxy.size(); ++f) correction.push_back(exact[f] - proxy[f]);
    const std::size_t worst = static_cast<std::size_t>(std::min_element(incumbent.gain.begin(), incumbent.gain.end()) - incumbent.gain.begin());
    TableProfile emphasised = incumbent.programme;
    for (double e : emphasis) {
      std::vector<double> offsets = correction;
      offsets[worst] += 2.0 * std::log(e);
      DesignProblem shifted = problem;
      shifted.set_flight_offsets(offsets);
      emphasised = solve(shifted, incumbent.programme);
      add(str_cat("round ", round, ": corrected", e > 1.0 ? str_cat(", ", incumbent.predicted.flights[worst].flight, " x", format_number(e)) : ""),
          emphasised, offsets);
    }
    for (double s : shares) {
      add(str_cat("round ", round, ": blend ", format_number(1.0 - s), " best + ", format_number(s), " emphasised"),
          blend_programmes(incumbent.programme, emphasised, s), {});
    }
  }
  r.chosen = choose();
  return r;
}

nlohmann::json SelectionResult::summary() const {
  nlohmann::json list = nlohmann::json::array();
  for (const SelectionCandidate& c : candidates) {
    nlohmann::json gain = nlohmann::json::object(), cof = nlohmann::json::object();
    for (std::size_t f = 0; f < c.gain.size(); ++f) gain[c.predicted.flights[f].flight] = c.gain[f], cof[c.predicted.flights[f].flight] = c.predicted.flights[f].cof_m;
    list.push_back({{"name", c.name}, {"gain", gain}, {"cof_m", cof}, {"worst_gain", c.worst_gain}, {"proxy_objective", c.proxy_objective},
                    {"offsets", c.offsets}, {"duration_min", c.programme.duration_min()}});
  }
  return {{"candidates", list}, {"repeats", repeats}, {"chosen", candidates.empty() ? "" : candidates[chosen].name},
          {"chosen_worst_gain", candidates.empty() ? 0.0 : candidates[chosen].worst_gain}};
}

}  // namespace gyrosid::design
