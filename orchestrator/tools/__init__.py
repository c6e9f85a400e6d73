"""Tools around the master: the libcosim runner, the FMI Cross-Check artifacts."""
