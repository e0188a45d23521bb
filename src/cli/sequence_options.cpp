#include "sequence_options.hpp"

#include "command_registry.hpp"

namespace seqtopo::cli {

pipeline::DescriptorOverrides descriptor_overrides(const std::optional<std::string>& descriptor,
                                                   const std::optional<std::string>& metric, std::optional<float> kappa,
                                                   unsigned threads) {
  pipeline::DescriptorOverrides d;
  if (descriptor) {
    d.descriptors = option_value("--descriptor", [&] { return pipeline::parse_descriptors(*descriptor); });
  }
  if (metric) d.metric = option_value("--metric", [&] { return similarity::parse_distance(*metric); });
  d.kappa = kappa;
  d.threads = resolve_threads(threads);
  return d;
}

}  // namespace seqtopo::cli
