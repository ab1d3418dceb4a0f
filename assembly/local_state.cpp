// Describing the exception being handled, for the message that ends a run.
#include "assembly/local_state.hpp"

#include <new>
#include <stdexcept>

namespace latticedyn {

void FirstError::record_current_exception(const std::string& where) {
  std::string what;
  try {
    throw;
  } catch (const std::domain_error& e) {
    what = std::string("an element was evaluated outside its domain: ") + e.what();
  } catch (const std::bad_alloc&) {
    what = "evaluating " + where + " ran out of memory";
  } catch (const std::exception& e) {
    what = "evaluating " + where + " failed: " + e.what();
  } catch (...) {
    what = "evaluating " + where + " failed with an exception that is not a std::exception";
  }
  record(what);
}

}  // namespace latticedyn
