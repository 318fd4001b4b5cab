"""The EDNC wire protocol: a sans-I/O codec shared by the center and the machines."""
