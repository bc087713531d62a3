#include "coflow/catalog.hpp"
#include "coflow/session.hpp"
#include "fluid/driver.hpp"

int main(int argc, char** argv) {
  return coflow::coupler::run_component("fluid", argc, argv, coflow::catalog(), coflow::fluid::run);
}
