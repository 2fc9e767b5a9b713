#include "mesh/hierarchy.hpp"
// quadtree: to be implemented
