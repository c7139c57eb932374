"""Design optimization with Optuna (multi-objective: tracking error and hip power)."""
