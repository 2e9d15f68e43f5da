"""The rule both report.py and final_table.py rank by (issue 13)."""

# A configuration whose final RMSE is below this many reference noise floors
# is not ranked: the reference's own error could account for the difference.
NO_VERDICT_FACTOR = 3
