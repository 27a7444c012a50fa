"""tread_wear's fleet layer: the C++ replay of every drive bag of a fleet on Dask distributed, cached per bag,
reduced per vehicle and fleet-wide (docs/fleet.md)."""
