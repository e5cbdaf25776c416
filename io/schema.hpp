// The one owner of the results schema (docs/formats.md "Results file layout" and "Lot
// summary"): every group of a results file and every column of the lot summary is described
// here once, as a table of (name, type, struct member, notes). The writer, the full reader
// (read_results) and the summary reader (read_summary_results) all walk these tables, so adding
// a dataset is one line here. The HDF5 type follows from the member's C++ type: double ->
// IEEE f64 LE, std::int64_t -> i64 LE, int -> i32 LE datasets / i64 attributes, std::uint8_t and
// bool -> u8, std::string and the statuses (io/status.hpp) -> variable-length UTF-8 strings.
#pragma once

#include "io/diagnosis.hpp"
#include "io/results.hpp"
#include "io/status.hpp"
#include "kernels/allan/stats.hpp"
#include "kernels/model/fit.hpp"
#include "kernels/powerlaw/names.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace allanlot::io::schema {

/// The layout this build writes and the newest it reads: root attribute `schema_version` of
/// results files and of lot_summary.h5. A file without it is version 1, the layout written
/// before the attribute existed (the same as version 1 with it).
inline constexpr std::int64_t kVersion = 1;
inline constexpr const char* kVersionAttribute = "schema_version";

enum class Kind { Dataset, Attribute };

/// Required: an always-written dataset that must be there. IfPresent: read when present, left
/// at its default otherwise (conditional datasets and every attribute are read this way).
enum class Need { Required, IfPresent };

/// A member of a record stored as one dataset or attribute of its group.
template <class Rec>
using Member =
    std::variant<double Rec::*, std::int64_t Rec::*, int Rec::*, std::string Rec::*,
                 kernels::FitStatus Rec::*, ChannelStatus Rec::*, std::vector<double> Rec::*,
                 std::vector<std::int64_t> Rec::*, std::vector<int> Rec::*,
                 std::vector<std::uint8_t> Rec::*, std::vector<std::string> Rec::*>;

template <class Rec>
struct Field {
  const char* name;
  Kind kind;
  Member<Rec> member;
  const char* notes;                      // units and meaning
  bool (*written)(const Rec&) = nullptr;  // written only when true; nullptr: always
  Need need = Need::Required;             // for always-written datasets
  bool summary = false;                   // also read by read_summary_results

  bool required() const { return kind == Kind::Dataset && !written && need == Need::Required; }
};

/// A member of a row stored as one element of a 1-D dataset per member (fit/'s term table).
template <class Row>
using ColumnMember =
    std::variant<double Row::*, std::int64_t Row::*, bool Row::*, std::string Row::*>;

template <class Row>
struct Column {
  const char* name;
  ColumnMember<Row> member;
  const char* notes;
  Need need = Need::Required;  // IfPresent numbers absent from a file read as NaN
  bool summary = false;        // also read by read_summary_results
};

// The groups of a results file, in the order their fields are written.
std::span<const Field<RecordingResult>> root_fields();            // "/" (free attributes follow)
std::span<const Field<ChannelResult>> channel_fields();           // the channel group's attributes
std::span<const Field<kernels::StatResult>> stat_fields();        // allan/<stat>/
std::span<const Column<TermRecord>> term_columns();               // fit/ and psd_fit/: per term
std::span<const Field<FitRecord>> fit_fields();                   // fit/ and psd_fit/
std::span<const Column<ReadoutRecord>> readout_columns();         // fit/readouts/
std::span<const Column<EffectRecord>> effect_columns();           // fit/effects/
std::span<const Field<PsdRecord>> psd_fields();                   // psd/
std::span<const Field<CrosscheckRecord>> crosscheck_fields();     // crosscheck/
std::span<const Field<DiagnosisRecord>> diagnosis_fields();       // diagnosis/ (+ free attributes)
std::span<const Field<kernels::QualityReport>> quality_fields();  // quality/
std::span<const Field<PowerLawRecord>> powerlaw_fields();         // powerlaw/
std::span<const Column<PowerLawLevelRecord>> powerlaw_columns();  // powerlaw/: per level

// Data editing and the dynamic deviation (io/schema_editing.cpp, docs/editing.md).
std::span<const Field<DriftRecord>> drift_fields();      // drift/
std::span<const Column<EditRecord>> edit_columns();      // edits/: one row per edit
std::span<const Field<DynamicRecord>> dynamic_fields();  // dynamic/ (oadev, 2-D, beside it)

/// Names of a channel group's subgroups.
inline constexpr const char* kAllan = "allan";
inline constexpr const char* kFit = "fit";
inline constexpr const char* kPsdFit = "psd_fit";
inline constexpr const char* kPsd = "psd";
inline constexpr const char* kCrosscheck = "crosscheck";
inline constexpr const char* kReadouts = "readouts";
inline constexpr const char* kEffects = "effects";
inline constexpr const char* kDiagnosis = "diagnosis";
inline constexpr const char* kQuality = "quality";
inline constexpr const char* kPowerLaw = "powerlaw";

inline constexpr const char* kDrift = "drift";
inline constexpr const char* kEdits = "edits";
inline constexpr const char* kDynamic = "dynamic";

/// The eq. (3) terms in the order of the lot summary's per-term columns.
inline constexpr std::array<const char*, 5> kTermNames = {"R", "K", "B", "N", "Q"};
/// The power-law levels alpha = 2, 1, 0, -1, -2 in the order of the lot summary's per-level
/// columns (h2, h2_sigma, ...).
inline constexpr std::array<const char*, 5> kLevelNames = kernels::powerlaw::kLevelKeys;

/// A member of a lot summary row: a scalar column, or a per-term array (one column per term).
template <class Row>
using RowMember =
    std::variant<std::string Row::*, double Row::*, std::int64_t Row::*, std::uint8_t Row::*,
                 std::int8_t Row::*, ChannelStatus Row::*, std::array<double, 5> Row::*,
                 std::array<std::string, 5> Row::*, std::array<std::uint8_t, 5> Row::*>;

template <class Row>
struct RowColumn {
  const char* name;  // for per-term arrays: the suffix after the term name ("" or "_sigma")
  RowMember<Row> member;
  const char* notes;
  /// Per-term arrays with the same nonzero block interleave, term by term (R, R_sigma, ..., K,
  /// K_sigma, ...); the record in HDF5 stores each array whole, in table order.
  int block = 0;
  /// The CSV text when it is not the plain value (e.g. empty detection flag without a fit).
  std::string (*csv)(const Row&, std::size_t term) = nullptr;
  /// The names the per-term array's columns start with: kTermNames (nullptr) or kLevelNames.
  const std::array<const char*, 5>* names = nullptr;
};

std::span<const RowColumn<SummaryRow>> summary_columns();        // /summary, lot_summary.csv
std::span<const RowColumn<StatisticsRow>> statistics_columns();  // /statistics, lot_statistics.csv

/// One column of the lot summary or lot statistics, typed by the schema: numbers (integers,
/// flags and NaN included) as double, strings and statuses as text.
struct TableColumn {
  std::string name;  // as in the CSV header
  bool numeric = false;
  std::vector<double> numbers;    // numeric columns
  std::vector<std::string> text;  // the others
};
/// The rows column by column, in CSV column order (for the Python module's read_lot_summary).
std::vector<TableColumn> summary_table(const std::vector<SummaryRow>& rows);
std::vector<TableColumn> statistics_table(const std::vector<StatisticsRow>& rows);

/// The summary rows as text columns in column order (name, one text per row): strings and
/// statuses as written, numbers with up to 10 significant digits, "" for NaN.
std::vector<std::pair<std::string, std::vector<std::string>>>
summary_text(const std::vector<SummaryRow>& rows);

}  // namespace allanlot::io::schema
