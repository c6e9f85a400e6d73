"""AXIR radar models: physics and algorithms in pure Python/numpy (no FMI imports)."""
