# The Embree API's tests (filled below).
