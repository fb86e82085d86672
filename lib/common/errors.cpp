#include "common/errors.h"

namespace ffd {

Error::Error(std::string message, Subject subject)
    : message_(std::move(message)), subject_(std::move(subject)), text_(message_) {}

void Error::set_place(std::string place) {
  place_ = std::move(place);
  text_ = place_.empty() ? message_ : place_ + ": " + message_;
}

}  // namespace ffd
