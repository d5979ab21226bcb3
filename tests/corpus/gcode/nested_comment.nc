G21 G90 (outer (inner) text)
G0 X0 Y0 Z1
M30
