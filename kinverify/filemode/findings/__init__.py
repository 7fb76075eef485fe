"""Findings: the severity table, one finding per cause, which checks each explains, accepted
differences, and the report section."""
