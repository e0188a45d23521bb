#pragma once
// The options of every command that reads a sequence (map, localize, similarity): how image folders are
// listed and which topic of a bag holds the images (INTERFACE.md, "Recordings and sessions").
#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>

#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"

namespace seqtopo::cli {

struct SequenceOptions {
  std::string image_topic;
  bool recursive = false;
  bool skip_unreadable = false;

  void apply(pipeline::SequenceInput& input) const {
    input.image_topic = image_topic;
    input.recursive = recursive;
    input.skip_unreadable = skip_unreadable;
  }
};

inline void add_sequence_options(CLI::App& app, SequenceOptions& o) {
  app.add_option("--image-topic", o.image_topic,
                 "bags: the sensor_msgs/Image or CompressedImage topic (default: the bag's only image topic)");
  app.add_flag("--recursive", o.recursive,
               "image folders: also the images of every subfolder, in natural order of their relative paths "
               "(a/2.png, a/10.png, b/1.png, b.png)");
  app.add_flag("--skip-unreadable", o.skip_unreadable,
               "image folders: leave out, with a warning listing them, entries named like images that cannot be "
               "read (dangling or looping links, folders, FIFOs, corrupt files) instead of stopping");
}

// --descriptor, --metric, --kappa and --threads as `map` and `localize` take them: the names parsed (an error names
// the option), the threads resolved (command_registry.hpp).
pipeline::DescriptorOverrides descriptor_overrides(const std::optional<std::string>& descriptor,
                                                   const std::optional<std::string>& metric, std::optional<float> kappa,
                                                   unsigned threads);

}  // namespace seqtopo::cli
