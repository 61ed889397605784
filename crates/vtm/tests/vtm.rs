//! VTM end to end on the paper's regions (the suite shared with the other relaxation
//! method, see `testkit::relaxation_tests`).
testkit::relaxation_tests!(cvtmesh_vtm::Vtm);
