// The tables of drift/, edits/ and dynamic/ (io/schema.hpp, docs/formats.md), and their groups'
// writer and reader, which io/results.cpp calls for every channel.
#include "io/error.hpp"
#include "io/hdf5_handle.hpp"
#include "io/schema.hpp"
#include "io/schema_h5.hpp"

namespace allanlot::io::schema {

namespace {
constexpr Kind D = Kind::Dataset;
constexpr Kind A = Kind::Attribute;
constexpr const char* kOadev2d = "oadev";
}  // namespace

std::span<const Field<DriftRecord>> drift_fields() {
  using R = DriftRecord;
  static const Field<R> t[] = {
      {"model", A, &R::model, "linear, quadratic, log or diffusion"},
      {"fitted_to", A, &R::fitted_to, "frequency or phase"},
      {"parameter", D, &R::parameter, "parameter names, e.g. offset, drift"},
      {"value", D, &R::value, "estimates, in unit"},
      {"sigma", D, &R::sigma, "standard uncertainties (noise model below)"},
      {"unit", D, &R::unit, "unit of each value"},
      {"noise_white_pm", A, &R::noise_white_pm, "white PM variance per sample, phase^2"},
      {"noise_white_fm", A, &R::noise_white_fm, "white FM variance per sample, rate^2"},
      {"noise_rw_fm", A, &R::noise_rw_fm, "random-walk FM increment variance, rate^2"},
      {"n_used", A, &R::n_used, "samples fitted"},
      {"t", D, &R::t, "s, residual block centres"},
      {"residual", D, &R::residual, "block means of the residuals against the model"},
  };
  return t;
}

std::span<const Column<EditRecord>> edit_columns() {
  using E = EditRecord;
  static const Column<E> t[] = {
      {"kind", &E::kind, "outlier or excluded"},
      {"first", &E::first, "first sample index"},
      {"last", &E::last, "last sample index (inclusive)"},
      {"t_start", &E::t_start, "s from the first sample"},
      {"t_end", &E::t_end, "s from the first sample"},
      {"value", &E::value, "the outlier's sample, channel units; NaN for a range"},
      {"sigmas", &E::sigmas, "the outlier's robust distance; NaN for a range"},
  };
  return t;
}

std::span<const Field<DynamicRecord>> dynamic_fields() {
  using R = DynamicRecord;
  static const Field<R> t[] = {
      {"m", D, &R::m, "averaging factors"},
      {"tau", D, &R::tau, "s"},
      {"t_center", D, &R::t_center, "s, each window's centre"},
      {"window", A, &R::window, "samples per window"},
      {"step", A, &R::step, "samples between windows"},
  };
  return t;
}

void write_editing_groups(hid_t channel_group, const ChannelResult& ch, const std::string& file) {
  const std::string& gp = ch.path;
  if (ch.drift) {
    h5::Handle g = create_group(channel_group, kDrift, file, gp + "/" + kDrift);
    write_fields(g.get(), *ch.drift, drift_fields(), file, gp + "/" + kDrift);
  }
  if (!ch.edits.empty()) {
    h5::Handle g = create_group(channel_group, kEdits, file, gp + "/" + kEdits);
    write_columns(g.get(), ch.edits, edit_columns(), file, gp + "/" + kEdits);
  }
  if (!ch.dynamic) return;
  const std::string object = gp + "/" + kDynamic;
  const DynamicRecord& d = *ch.dynamic;
  h5::Handle g = create_group(channel_group, kDynamic, file, object);
  write_fields(g.get(), d, dynamic_fields(), file, object);
  const hsize_t dims[2] = {d.t_center.size(), d.tau.size()};
  if (dims[0] * dims[1] != d.oadev.size())
    throw Error(file, object, "dynamic oadev is not windows x taus");
  h5::Handle space =
      h5::check(H5Screate_simple(2, dims, nullptr), H5Sclose, file, object, "H5Screate_simple");
  h5::Handle ds = h5::check(H5Dcreate2(g.get(), kOadev2d, H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                                       H5P_DEFAULT, H5P_DEFAULT),
                            H5Dclose, file, object + "/oadev", "H5Dcreate2");
  if (!d.oadev.empty())
    h5::check(H5Dwrite(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.oadev.data()),
              file, object + "/oadev", "H5Dwrite");
}

namespace {

std::vector<double> read_matrix(hid_t g, std::size_t rows, std::size_t cols,
                                const std::string& file, const std::string& object) {
  h5::Handle ds = h5::check(H5Dopen2(g, kOadev2d, H5P_DEFAULT), H5Dclose, file, object, "H5Dopen2");
  h5::Handle space = h5::check(H5Dget_space(ds.get()), H5Sclose, file, object, "H5Dget_space");
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.get()) != 2 ||
      H5Sget_simple_extent_dims(space.get(), dims, nullptr) != 2 || dims[0] != rows ||
      dims[1] != cols)
    throw Error(file, object, "expected a 2-D dataset of t_center x tau");
  std::vector<double> v(rows * cols);
  if (!v.empty())
    h5::check(H5Dread(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), file,
              object, "H5Dread");
  return v;
}

}  // namespace

void read_editing_groups(hid_t channel_group, ChannelResult& ch, Depth depth,
                         const std::string& file) {
  // The lot summary needs none of them.
  if (depth != Depth::Full) return;
  const std::string& gp = ch.path;
  if (has_link(channel_group, kDrift)) {
    h5::Handle g = open_group(channel_group, kDrift, file, gp + "/" + kDrift);
    ch.drift.emplace();
    read_fields(g.get(), *ch.drift, drift_fields(), depth, file, gp + "/" + kDrift);
  }
  if (has_link(channel_group, kEdits)) {
    h5::Handle g = open_group(channel_group, kEdits, file, gp + "/" + kEdits);
    ch.edits = read_columns(g.get(), edit_columns(), depth, file, gp + "/" + kEdits);
  }
  if (!has_link(channel_group, kDynamic)) return;
  const std::string object = gp + "/" + kDynamic;
  h5::Handle g = open_group(channel_group, kDynamic, file, object);
  DynamicRecord d;
  read_fields(g.get(), d, dynamic_fields(), depth, file, object);
  d.oadev = read_matrix(g.get(), d.t_center.size(), d.tau.size(), file, object + "/oadev");
  ch.dynamic = std::move(d);
}

}  // namespace allanlot::io::schema
