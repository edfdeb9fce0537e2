"""What two or more domains share: errors, config validation, results, atomic I/O, reports."""
