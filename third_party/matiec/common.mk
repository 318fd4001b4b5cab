AM_CXXFLAGS = -g -Wall -Wpointer-arith -Wwrite-strings -Wno-unused 


