(a program that never moves)
G21 G90 G17
M3 S1000
M5
M30
