// Face codes of the id pass; mirrored by cityshade/interior/_faces.py.
#ifndef INTERIOR_FACES_GLSL
#define INTERIOR_FACES_GLSL
#define FACE_NONE 0
#define FACE_EXTERIOR 1
#define FACE_CEILING 2
#define FACE_FLOOR 3
#define FACE_WALL_X 4
#define FACE_WALL_Z 5
#define FACE_FURNITURE 6
#define FACE_CURTAIN 7
#define FACE_ROOF 8
#define FACE_GROUND 9
#endif
