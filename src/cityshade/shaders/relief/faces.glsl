// Faces of the relief by outward normal in map space; cityshade.relief._reference uses the same ids.
#ifndef RELIEF_FACES_GLSL
#define RELIEF_FACES_GLSL
#define FACE_FRONT 0
#define FACE_NEG_X 1
#define FACE_POS_X 2
#define FACE_NEG_Y 3
#define FACE_POS_Y 4
#endif
