"""The ground floor: errors, the wall-clock budget and the one unit system; imports nothing else of mech."""
