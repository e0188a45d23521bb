// seqtopo.OnlineMapper: the online mapper (mapping/online_mapper.hpp) fed one frame at a time from Python.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "seqtopo/mapping/online_mapper.hpp"
#include "seqtopo/pipeline/online_map.hpp"
#include "seqtopo/similarity/distance.hpp"

namespace seqtopo::python {
namespace {

using mapping::OnlineEvent;
using mapping::OnlineEventKind;
using mapping::OnlineMapConfig;
using mapping::OnlineMapper;

// One event as the dict of its events.jsonl line (INTERFACE.md).
py::dict event_dict(const OnlineEvent& e) {
  py::dict d;
  d["frame"] = e.frame;
  d["event"] = std::string(mapping::to_string(e.kind));
  d["i"] = e.i;
  d["j"] = e.j;
  d["revisit"] = e.revisit;
  if (e.kind != OnlineEventKind::place_merge && e.kind != OnlineEventKind::session_break)
    d["direction"] = std::string(align::to_string(e.direction));
  if (e.candidate) d["candidate"] = *e.candidate;
  if (e.kind == OnlineEventKind::loop_closure || e.kind == OnlineEventKind::revisit_begin ||
      e.kind == OnlineEventKind::revisit_end || e.kind == OnlineEventKind::revisit_candidate) {
    d["e_value"] = e.e_value ? py::cast(*e.e_value) : py::none();
  }
  switch (e.kind) {
    case OnlineEventKind::loop_closure:
      d["confidence"] = e.confidence;
      d["score"] = e.score;
      break;
    case OnlineEventKind::revisit_begin:
      d["score"] = e.score;
      d["delay"] = e.frame - e.first;
      break;
    case OnlineEventKind::revisit_candidate:
      d["start"] = py::make_tuple(e.first, e.last);
      d["score"] = e.score;
      d["delay"] = e.frame - e.first;
      break;
    case OnlineEventKind::revisit_end:
      d["first"] = e.first;
      d["last"] = e.last;
      d["frames"] = e.frames;
      d["score"] = e.score;
      break;
    case OnlineEventKind::junction:
      d["joining"] = e.joining;
      break;
    case OnlineEventKind::place_merge:
      d["places"] = py::make_tuple(e.first, e.last);
      break;
    case OnlineEventKind::correction: {
      py::list withdrawn;
      for (const auto& [i, j] : e.withdrawn) withdrawn.append(py::make_tuple(i, j));
      d["withdrawn"] = withdrawn;
      d["reason"] = e.reason;
      break;
    }
    case OnlineEventKind::session_break:
      d["gap"] = e.gap;
      d["median_interval"] = e.median_interval;
      break;
  }
  return d;
}

py::list event_list(const std::vector<OnlineEvent>& events) {
  py::list out;
  for (const auto& e : events) out.append(event_dict(e));
  return out;
}

// A NumPy copy of the mapper's values.
template <typename T>
py::array_t<T> copy_array(std::span<const T> values) {
  return py::array_t<T>(static_cast<py::ssize_t>(values.size()), values.data());
}

std::vector<float> float_vector(const py::handle& values, const char* what) {
  const auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(values);
  if (!array || array.ndim() != 1) throw py::value_error(std::string(what) + " must be a 1-D array of numbers");
  return {array.data(), array.data() + array.size()};
}

// The mapper with the descriptors it uses for image frames (joint histograms and patch thumbnails, fused, as
// `seqtopo map --online`).
struct PyOnlineMapper {
  OnlineMapper mapper;
  pipeline::OnlineImageRows image_rows;
  std::optional<bool> images;  // the kind of the first frame: images and descriptors do not mix
  bool finished = false;       // finish() was called: the sequence has ended

  void check_open(const char* call) const {
    if (finished) {
      throw std::runtime_error(std::string(call) +
                               ": a frame after finish() (the sequence has ended; make a new OnlineMapper)");
    }
  }

  py::list add(const py::handle& frame) {
    check_open("add");
    const auto array = py::array::ensure(frame);
    if (!array) throw py::value_error("add: expected an image (H x W or H x W x 3 uint8) or a 1-D descriptor");
    const bool image = array.ndim() == 2 || array.ndim() == 3;
    if (images && *images != image) {
      throw py::value_error(image ? "add: an image after descriptors (one kind of frame per mapper)"
                                  : "add: a descriptor after images (one kind of frame per mapper)");
    }
    if (!images) images = image;
    if (image) {
      // Only uint8: a cast of floats (0..1, or 0..255 with fractions) would map other pictures than the same ones
      // read from files.
      if (array.dtype().kind() != 'u' || array.dtype().itemsize() != 1) {
        throw py::value_error("add: an image must be of uint8 (0..255), got " + std::string(py::str(array.dtype())) +
                              "; convert it first, e.g. (image * 255).round().astype(numpy.uint8) for values in 0..1");
      }
      const auto pixels = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(frame);
      if (!pixels || (pixels.ndim() == 3 && pixels.shape(2) != 3)) {
        throw py::value_error("add: an image must be H x W (grey) or H x W x 3 (RGB) of uint8");
      }
      const auto h = static_cast<int>(pixels.shape(0)), w = static_cast<int>(pixels.shape(1));
      RgbImage rgb(w, h);
      const std::uint8_t* p = pixels.data();
      for (std::size_t k = 0; k < static_cast<std::size_t>(w) * static_cast<std::size_t>(h); ++k) {
        for (std::size_t c = 0; c < 3; ++c) rgb.pixels[3 * k + c] = pixels.ndim() == 3 ? p[3 * k + c] : p[k];
      }
      std::vector<OnlineEvent> events;
      try {
        const py::gil_scoped_release release;
        events = image_rows.feed(mapper, image_rows.add(rgb));
      } catch (const std::invalid_argument& e) {
        throw py::value_error(std::string("add: frame ") + std::to_string(mapper.frames()) + ": " + e.what());
      }
      return event_list(events);
    }
    if (array.ndim() != 1) {
      throw py::value_error("add: expected an image (H x W or H x W x 3 uint8) or a 1-D descriptor");
    }
    const std::vector<float> descriptor = float_vector(frame, "descriptor");
    std::vector<OnlineEvent> events;
    {
      const py::gil_scoped_release release;
      events = mapper.add_descriptor(descriptor);
    }
    return event_list(events);
  }
};

}  // namespace

void bind_online(py::module_& m) {
  py::class_<OnlineMapConfig> c(m, "OnlineMapConfig",
                                "Settings of the online mapper (docs/online.md); every field a keyword argument.");
  c.def(py::init([](const std::string& distance, std::size_t contrast_window, float contrast_offset, float gap,
                    std::optional<float> cap, std::optional<double> max_e_value,
                    std::optional<double> candidate_e_value, float threshold, std::size_t min_separation, bool reverse,
                    std::size_t reach, float x_drop, std::size_t min_revisit_frames, std::size_t patience,
                    std::size_t island_sample, bool adapt_offset, std::size_t early_fit_frames) {
          OnlineMapConfig config;
          config.distance = similarity::parse_distance(distance);
          config.score.contrast_window = contrast_window;
          config.score.contrast_offset = contrast_offset;
          config.search.gap = gap;
          config.search.cap = cap;
          config.significance.max_e_value = max_e_value;
          config.candidate_e_value = candidate_e_value;
          config.significance.threshold = threshold;
          config.island_sample = island_sample;
          config.phase.adapt_offset = adapt_offset;
          config.early_fit_frames = early_fit_frames;
          config.search.min_separation = min_separation;
          config.search.reverse = reverse;
          config.reach = reach;
          config.x_drop = x_drop;
          config.min_revisit_frames = min_revisit_frames;
          config.patience = patience;
          mapping::validate(config);
          return config;
        }),
        py::kw_only(), py::arg("distance") = "cosine",
        py::arg("contrast_window") = OnlineMapConfig{}.score.contrast_window,
        py::arg("contrast_offset") = OnlineMapConfig{}.score.contrast_offset,
        py::arg("gap") = OnlineMapConfig{}.search.gap, py::arg("cap") = OnlineMapConfig{}.search.cap,
        py::arg("max_e_value") = OnlineMapConfig{}.significance.max_e_value,
        py::arg("candidate_e_value") = OnlineMapConfig{}.candidate_e_value,
        py::arg("threshold") = OnlineMapConfig{}.significance.threshold,
        py::arg("min_separation") = OnlineMapConfig{}.search.min_separation,
        py::arg("reverse") = OnlineMapConfig{}.search.reverse, py::arg("reach") = OnlineMapConfig{}.reach,
        py::arg("x_drop") = OnlineMapConfig{}.x_drop,
        py::arg("min_revisit_frames") = OnlineMapConfig{}.min_revisit_frames,
        py::arg("patience") = OnlineMapConfig{}.patience, py::arg("island_sample") = OnlineMapConfig{}.island_sample,
        py::arg("adapt_offset") = OnlineMapConfig{}.phase.adapt_offset,
        py::arg("early_fit_frames") = OnlineMapConfig{}.early_fit_frames);
  c.def_property_readonly("distance",
                          [](const OnlineMapConfig& x) { return std::string(similarity::distance_name(x.distance)); });
  c.def_property_readonly("contrast_window",
                          section_getter(&OnlineMapConfig::score, &align::ScoreSettings::contrast_window));
  c.def_property_readonly("contrast_offset",
                          section_getter(&OnlineMapConfig::score, &align::ScoreSettings::contrast_offset));
  c.def_property_readonly("gap", section_getter(&OnlineMapConfig::search, &align::SearchSettings::gap));
  c.def_property_readonly("cap", section_getter(&OnlineMapConfig::search, &align::SearchSettings::cap));
  c.def_property_readonly("max_e_value",
                          section_getter(&OnlineMapConfig::significance, &align::SignificanceSettings::max_e_value));
  c.def_readonly("candidate_e_value", &OnlineMapConfig::candidate_e_value);
  c.def_property_readonly("threshold",
                          section_getter(&OnlineMapConfig::significance, &align::SignificanceSettings::threshold));
  c.def_readonly("island_sample", &OnlineMapConfig::island_sample);
  c.def_property_readonly("adapt_offset", section_getter(&OnlineMapConfig::phase, &align::PhaseSettings::adapt_offset));
  c.def_readonly("early_fit_frames", &OnlineMapConfig::early_fit_frames);
  c.def_property_readonly("min_separation",
                          section_getter(&OnlineMapConfig::search, &align::SearchSettings::min_separation));
  c.def_property_readonly("reverse", section_getter(&OnlineMapConfig::search, &align::SearchSettings::reverse));
  c.def_readonly("reach", &OnlineMapConfig::reach);
  c.def_readonly("x_drop", &OnlineMapConfig::x_drop);
  c.def_readonly("min_revisit_frames", &OnlineMapConfig::min_revisit_frames);
  c.def_readonly("patience", &OnlineMapConfig::patience);

  py::class_<PyOnlineMapper>(
      m, "OnlineMapper",
      "Maps a sequence while its frames arrive (docs/online.md): add() takes the next frame, "
      "an image (H x W or H x W x 3 uint8: joint histogram and patch thumbnail, fused as the offline "
      "default) or a 1-D descriptor (cosine), and returns the events it caused as dicts (the events.jsonl fields).")
      .def(py::init([](std::optional<OnlineMapConfig> config) {
             return PyOnlineMapper{OnlineMapper(config.value_or(OnlineMapConfig{})), pipeline::OnlineImageRows{},
                                   std::nullopt, false};
           }),
           py::arg("config") = py::none())
      .def("add", &PyOnlineMapper::add, py::arg("frame"))
      .def(
          "add_similarity",
          [](PyOnlineMapper& self, const py::handle& row) {
            self.check_open("add_similarity");
            const std::vector<float> values = float_vector(row, "similarity row");
            std::vector<OnlineEvent> events;
            {
              const py::gil_scoped_release release;
              events = self.mapper.add_similarity(values);
            }
            return event_list(events);
          },
          py::arg("row"), "The next frame as its similarity to every earlier frame (frames values).")
      .def(
          "add_similarities",
          [](PyOnlineMapper& self, const py::list& rows) {
            self.check_open("add_similarities");
            std::vector<std::vector<float>> values;
            for (const auto& row : rows) values.push_back(float_vector(row, "similarity row"));
            std::vector<OnlineEvent> events;
            {
              const py::gil_scoped_release release;
              events = self.mapper.add_similarities(values);
            }
            return event_list(events);
          },
          py::arg("rows"),
          "The next frame as several similarity rows (one per descriptor), enhanced apart and averaged.")
      .def(
          "add_scores",
          [](PyOnlineMapper& self, const py::handle& row) {
            self.check_open("add_scores");
            const std::vector<float> values = float_vector(row, "score row");
            return event_list(self.mapper.add_scores(values));
          },
          py::arg("scores"),
          "The next frame as its alignment scores to frames 0 .. t - min_separation, aligned as they are.")
      .def("finish",
           [](PyOnlineMapper& self) {
             self.finished = true;
             return event_list(self.mapper.finish());
           })
      .def_property_readonly("frames", [](const PyOnlineMapper& self) { return self.mapper.frames(); })
      .def_property_readonly("config", [](const PyOnlineMapper& self) { return self.mapper.config(); })
      .def(
          "loop_closures",
          [](const PyOnlineMapper& self) {
            py::list out;
            for (const auto& lc : self.mapper.loop_closures()) {
              out.append(
                  py::make_tuple(lc.i, lc.j, std::string(align::to_string(lc.direction)), lc.confidence, lc.revisit));
            }
            return out;
          },
          "The loop closures standing now: (i, j, direction, confidence, revisit), by i then j.")
      .def_property_readonly("forward_row",
                             [](const PyOnlineMapper& self) { return copy_array(self.mapper.forward_row()); })
      .def_property_readonly("reverse_row",
                             [](const PyOnlineMapper& self) { return copy_array(self.mapper.reverse_row()); })
      .def_property_readonly(
          "threshold", [](const PyOnlineMapper& self) { return self.mapper.threshold(); },
          "The score a revisit needs at the next frame (from max_e_value and the statistics after the last).")
      .def_property_readonly(
          "statistics",
          [](const PyOnlineMapper& self) -> py::object {
            const auto& st = self.mapper.statistics();
            if (!st.valid()) return py::none();
            py::dict d;
            d["lambda"] = st.lambda;
            d["k"] = st.k;
            d["area"] = st.area;
            d["fitted"] = st.fitted;
            d["fitted_to"] = self.mapper.statistics_from_table() ? "table" : "islands";
            return d;
          },
          "The statistics of the last frame (lambda, k, area, fitted, fitted_to: 'islands', or 'table' while the "
          "islands are too few), None before a fit.")
      .def_property_readonly(
          "contrast_offset", [](const PyOnlineMapper& self) { return self.mapper.contrast_offset(); },
          "The contrast offset of the next frame: the config's, raised while chance paths grow with the sequence.")
      .def_property_readonly(
          "low_information_frames", [](const PyOnlineMapper& self) { return self.mapper.low_information_frames(); },
          "The images so far judged of little information (dark or near-uniform) as they arrived: no evidence of a "
          "revisit (docs/online.md).")
      .def_property_readonly("island_scores",
                             [](const PyOnlineMapper& self) { return copy_array<double>(self.mapper.island_scores()); })
      .def_property_readonly("last_scores",
                             [](const PyOnlineMapper& self) { return copy_array(self.mapper.last_scores()); });
}

}  // namespace seqtopo::python
