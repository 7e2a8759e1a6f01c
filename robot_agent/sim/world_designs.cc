#include "robot_agent/sim/world_designs.h"

#include <cmath>

#include "robot_agent/sim/appearance.h"
#include "robot_agent/sim/world_builder.h"

namespace fleetmap::sim {
namespace {

using V = Eigen::Vector2d;

// A poster on a horizontal wall face at height y, from x to x + width.
void PosterX(WorldBuilder* b, const std::string& label, double x, double y, double z_min,
             double z_max, const Rgb& color, double width = 0.6) {
  b->AddPoster(label, V(x, y), V(x + width, y), z_min, z_max, color);
}
// A poster on a vertical wall face at x, from y to y + width.
void PosterY(WorldBuilder* b, const std::string& label, double x, double y, double z_min,
             double z_max, const Rgb& color, double width = 0.6) {
  b->AddPoster(label, V(x, y), V(x, y + width), z_min, z_max, color);
}

}  // namespace

World MakeRectangleWorld() {
  WorldBuilder b("rectangle", 0.05, V(21.3, 17.0));
  b.Carve(V(0.2, 0.2), V(21.1, 16.8));   // 2 m corridor ring inside 0.2 m outer walls
  b.Fill(V(2.2, 2.2), V(19.1, 14.8));    // the solid inner block
  b.AddPlace("Corner_SW", 1.2, 1.2, 0.0);
  b.AddPlace("Corner_SE", 20.1, 1.2, M_PI / 2);
  b.AddPlace("Corner_NE", 20.1, 15.8, M_PI);
  b.AddPlace("Corner_NW", 1.2, 15.8, -M_PI / 2);
  b.AddPlace("South_Mid", 10.65, 1.2, 0.0);
  b.AddPlace("North_Mid", 10.65, 15.8, M_PI);
  return b.Build();
}

World MakeDepartmentWorld() {
  WorldBuilder b("department", 0.05, V(54.2, 22.0));
  // South rooms, Lab_1 = rooms 2 and 3 joined.
  b.RoomsAlongX(0.2, 9, 6.0, 0.2, 5.8, 5.8, 6.0, "Room_S");
  b.Carve(V(6.2, 0.2), V(18.0, 5.8));
  b.Carve(V(0.2, 6.0), V(54.0, 8.0));    // south corridor
  b.Carve(V(0.2, 6.0), V(2.2, 16.0));    // west end corridor
  b.Carve(V(52.0, 6.0), V(54.0, 16.0));  // east end corridor
  b.Carve(V(0.2, 14.0), V(54.0, 16.0));  // north corridor
  // Rooms between the corridors, doors alternating south / north.
  for (int i = 0; i < 8; ++i) {
    const double left = 2.4 + 6.2 * i;
    const bool south = i % 2 == 0;
    b.RoomsAlongX(left, 1, 6.2, 8.2, 13.8, south ? 8.0 : 13.8, south ? 8.2 : 14.0);
    b.AddPlace("Room_M" + std::to_string(i + 1), left + 3.0, 11.0);
  }
  // North rooms, Lab_2 = rooms 7 and 8 joined.
  b.RoomsAlongX(0.2, 9, 6.0, 16.2, 21.8, 16.0, 16.2, "Room_N");
  b.Carve(V(36.2, 16.2), V(48.0, 21.8));
  b.AddPlace("Lab_1", 12.1, 4.0, M_PI / 2);
  b.AddPlace("Lab_2", 42.1, 18.0, -M_PI / 2);
  b.AddPlace("Corridor_S_West", 1.2, 7.0, 0.0);
  b.AddPlace("Corridor_S_Mid", 27.1, 7.0, 0.0);
  b.AddPlace("Corridor_S_East", 53.0, 7.0, M_PI / 2);
  b.AddPlace("Corridor_N_East", 53.0, 15.0, M_PI);
  b.AddPlace("Corridor_N_Mid", 27.1, 15.0, M_PI);
  b.AddPlace("Corridor_N_West", 1.2, 15.0, -M_PI / 2);
  // Lab furniture and a green cabinet (same colour family as robot 1's marker).
  b.Fill(V(8.0, 1.5), V(10.0, 2.5));
  b.Fill(V(14.0, 1.5), V(16.0, 2.5));
  b.Fill(V(38.0, 19.5), V(40.0, 20.5));
  b.Fill(V(44.0, 19.5), V(46.0, 20.5));
  b.AddColouredBox("cabinet_green", V(47.0, 21.2), V(47.8, 21.8), 1.2, kPosterGreen);
  b.AddColouredBox("cabinet_blue", V(0.4, 1.0), V(1.0, 2.0), 1.0, kPosterBlue);
  // Posters on the corridor walls, some at marker height.
  PosterX(&b, "poster_green_s1", 9.0, 8.0, 0.3, 0.8, kPosterGreen);
  PosterX(&b, "poster_blue_s2", 24.0, 8.0, 1.0, 1.6, kPosterBlue);
  PosterX(&b, "poster_orange_s3", 36.0, 8.0, 0.4, 0.9, kPosterOrange);
  PosterX(&b, "poster_magenta_s4", 48.0, 8.0, 1.0, 1.5, kPosterMagenta);
  PosterX(&b, "poster_blue_s5", 12.5, 6.0, 0.9, 1.5, kPosterBlue);
  PosterX(&b, "poster_green_s6", 30.0, 6.0, 1.0, 1.6, kPosterGreen);
  PosterX(&b, "poster_orange_s7", 41.5, 6.0, 0.35, 0.75, kPosterOrange);
  PosterX(&b, "poster_magenta_n1", 7.0, 14.0, 0.4, 0.9, kPosterMagenta);
  PosterX(&b, "poster_green_n2", 19.0, 14.0, 0.35, 0.7, kPosterGreen);
  PosterX(&b, "poster_blue_n3", 31.0, 14.0, 1.0, 1.6, kPosterBlue);
  PosterX(&b, "poster_green_n4", 44.0, 14.0, 1.1, 1.7, kPosterGreen);
  PosterX(&b, "poster_orange_n5", 25.0, 16.0, 1.0, 1.5, kPosterOrange);
  PosterX(&b, "poster_green_n6", 33.5, 16.0, 0.3, 0.8, kPosterGreen);
  PosterY(&b, "poster_blue_w1", 0.2, 10.0, 0.4, 0.9, kPosterBlue);
  PosterY(&b, "poster_green_e1", 54.0, 11.0, 0.9, 1.5, kPosterGreen);
  return b.Build();
}

World MakeBuildingWorld() {
  WorldBuilder b("building", 0.1, V(160.0, 84.0));
  // The ring corridor (2.4 m wide) and a cross corridor through the middle.
  b.Carve(V(6.4, 6.4), V(153.6, 8.8));
  b.Carve(V(6.4, 75.2), V(153.6, 77.6));
  b.Carve(V(6.4, 6.4), V(8.8, 77.6));
  b.Carve(V(151.2, 6.4), V(153.6, 77.6));
  b.Carve(V(78.8, 8.8), V(81.2, 75.2));
  // Rooms only along parts of the ring: the rest is long plain wall on both sides.
  b.RoomsAlongX(6.4, 5, 8.0, 0.2, 6.2, 6.2, 6.4, "Room_S");
  b.RoomsAlongX(110.4, 5, 8.0, 0.2, 6.2, 6.2, 6.4, "Room_SE");
  b.RoomsAlongX(9.0, 4, 8.0, 9.0, 15.0, 8.8, 9.0, "Room_SI");
  b.RoomsAlongX(119.0, 4, 8.0, 9.0, 15.0, 8.8, 9.0, "Room_SEI");
  b.RoomsAlongX(30.4, 6, 8.0, 77.8, 83.8, 77.6, 77.8, "Room_N");
  b.RoomsAlongX(90.0, 5, 8.0, 69.0, 75.0, 75.0, 75.2, "Room_NI");
  b.RoomsAlongY(10.4, 7, 9.0, 0.2, 6.2, 6.2, 6.4, "Room_W");
  b.RoomsAlongY(20.0, 4, 9.0, 9.0, 15.0, 8.8, 9.0, "Room_WI");
  b.RoomsAlongY(30.0, 2, 9.0, 153.8, 159.8, 153.6, 153.8, "Room_E");
  b.AddPlace("Corner_SW", 7.6, 7.6, 0.0);
  b.AddPlace("Corner_SE", 152.4, 7.6, M_PI / 2);
  b.AddPlace("Corner_NE", 152.4, 76.4, M_PI);
  b.AddPlace("Corner_NW", 7.6, 76.4, -M_PI / 2);
  b.AddPlace("South_Mid", 80.0, 7.6, 0.0);
  b.AddPlace("North_Mid", 80.0, 76.4, M_PI);
  b.AddPlace("West_Mid", 7.6, 42.0, -M_PI / 2);
  b.AddPlace("East_Mid", 152.4, 42.0, M_PI / 2);
  b.AddPlace("Cross_Mid", 80.0, 42.0, M_PI / 2);
  PosterX(&b, "poster_green_1", 20.0, 6.4, 0.35, 0.8, kPosterGreen);
  PosterX(&b, "poster_blue_1", 128.0, 8.8, 1.0, 1.6, kPosterBlue);
  PosterX(&b, "poster_orange_1", 60.0, 77.6, 0.4, 0.9, kPosterOrange);
  PosterX(&b, "poster_magenta_1", 100.0, 75.2, 0.9, 1.5, kPosterMagenta);
  PosterY(&b, "poster_green_2", 6.4, 30.0, 1.0, 1.6, kPosterGreen);
  PosterY(&b, "poster_blue_2", 8.8, 60.0, 0.3, 0.8, kPosterBlue);
  PosterY(&b, "poster_green_3", 78.8, 30.0, 0.4, 0.9, kPosterGreen);
  PosterY(&b, "poster_orange_2", 153.6, 50.0, 1.0, 1.5, kPosterOrange);
  return b.Build();
}

std::vector<std::string> DesignedWorldNames() { return {"rectangle", "department", "building"}; }

bool MakeWorldByName(const std::string& name, World* world) {
  if (name == "rectangle") {
    *world = MakeRectangleWorld();
  } else if (name == "department") {
    *world = MakeDepartmentWorld();
  } else if (name == "building") {
    *world = MakeBuildingWorld();
  } else {
    return false;
  }
  return true;
}

}  // namespace fleetmap::sim
