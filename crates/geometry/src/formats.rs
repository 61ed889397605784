//! Region input formats besides the project JSON: Triangle .poly, GeoJSON, plain loop lists.
