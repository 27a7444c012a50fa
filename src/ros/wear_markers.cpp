#include "tread_wear/ros/wear_markers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tread_wear {
namespace {

/// Smallest label height [m] (a wheel without a patch yet still gets a readable label).
constexpr double kMinTextHeightM = 0.01;

std_msgs::ColorRGBA rgba(double r, double g, double b, double a = 1.0) {
  std_msgs::ColorRGBA c;
  c.r = static_cast<float>(r);
  c.g = static_cast<float>(g);
  c.b = static_cast<float>(b);
  c.a = static_cast<float>(a);
  return c;
}

/// Blue -> green -> yellow ramp for t in [0, 1] (viridis-like end points).
std_msgs::ColorRGBA ramp(double t) {
  t = std::min(1.0, std::max(0.0, t));
  if (t < 0.5) {
    const double u = t / 0.5;
    return rgba(0.27 * (1 - u) + 0.13 * u, 0.00 * (1 - u) + 0.57 * u, 0.33 * (1 - u) + 0.55 * u);
  }
  const double u = (t - 0.5) / 0.5;
  return rgba(0.13 * (1 - u) + 0.99 * u, 0.57 * (1 - u) + 0.91 * u, 0.55 * (1 - u) + 0.14 * u);
}

geometry_msgs::Point point(double x, double y, double z) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

/// Adds two triangles for the rectangle [x0, x1] x [y0, y1] in one colour.
void addCell(visualization_msgs::Marker* m, double x0, double x1, double y0, double y1, double z,
             const std_msgs::ColorRGBA& c) {
  const geometry_msgs::Point p00 = point(x0, y0, z), p10 = point(x1, y0, z), p11 = point(x1, y1, z),
                             p01 = point(x0, y1, z);
  for (const geometry_msgs::Point& p : {p00, p10, p11, p00, p11, p01}) {
    m->points.push_back(p);
    m->colors.push_back(c);
  }
}

visualization_msgs::Marker base(const std::string& ns, const std::string& frame_id, const ros::Time& stamp,
                                int type) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame_id;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = 0;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color = rgba(1, 1, 1);
  return m;
}

}  // namespace

void appendWheelMarkers(const std::string& wheel, const std::string& frame_id, const ros::Time& stamp,
                        const PatchFields& fields, const WearResult& result, const WheelOutput& output,
                        visualization_msgs::MarkerArray* array, const WheelInputs* inputs) {
  const int nx = fields.n_x_nodes, ny = fields.n_strips;
  const double b = result.half_width_m;
  if (nx >= 2 && ny >= 1 && b > 0.0) {
    visualization_msgs::Marker wear = base(wheel + "/wear", frame_id, stamp, visualization_msgs::Marker::TRIANGLE_LIST);
    visualization_msgs::Marker zones =
        base(wheel + "/zones", frame_id, stamp, visualization_msgs::Marker::TRIANGLE_LIST);
    // Log colour scale over the positive local wear rates of this patch.
    double lo = INFINITY, hi = 0.0;
    for (double w : fields.wear_kg_per_m3)
      if (w > 0.0) {
        lo = std::min(lo, w);
        hi = std::max(hi, w);
      }
    const double log_lo = std::log(lo), span = hi > lo ? std::log(hi) - log_lo : 1.0;
    const double zone_offset = 2.5 * b;
    for (int j = 0; j < ny; ++j) {
      const double y0 = j == 0 ? -b : 0.5 * (fields.y_m[j - 1] + fields.y_m[j]);
      const double y1 = j == ny - 1 ? b : 0.5 * (fields.y_m[j] + fields.y_m[j + 1]);
      for (int i = 0; i + 1 < nx; ++i) {
        const double w =
            0.5 * (fields.wear_kg_per_m3[fields.index(i, j)] + fields.wear_kg_per_m3[fields.index(i + 1, j)]);
        const double t = w > 0.0 && std::isfinite(log_lo) ? (std::log(w) - log_lo) / span : 0.0;
        addCell(&wear, fields.x_m[i + 1], fields.x_m[i], y0, y1, 0.0, ramp(t));
        const unsigned char s = std::max(fields.state[fields.index(i, j)], fields.state[fields.index(i + 1, j)]);
        const std_msgs::ColorRGBA zc =
            s == 0 ? rgba(0.1, 0.7, 0.2) : (s == 1 ? rgba(0.95, 0.8, 0.1) : rgba(0.85, 0.1, 0.1));
        addCell(&zones, fields.x_m[i + 1], fields.x_m[i], y0 + zone_offset, y1 + zone_offset, 0.0, zc);
      }
    }
    array->markers.push_back(wear);
    array->markers.push_back(zones);
  }
  // Two lines ahead of the leading edge, centred across both patches (wear at y = 0, zones at y = 2.5 b), in the
  // road plane so that a view from above does not put them over the patch; sized to the patch so they stay
  // readable beside it at any tire size.
  const double patch_size_m = std::max(result.half_length_m, b);
  const double text_height_m = std::max(kMinTextHeightM, 0.25 * patch_size_m);
  visualization_msgs::Marker label =
      base(wheel + "/label", frame_id, stamp, visualization_msgs::Marker::TEXT_VIEW_FACING);
  label.pose.position.x = result.half_length_m + 1.5 * text_height_m;
  label.pose.position.y = 1.25 * b;
  label.scale.z = text_height_m;
  char text[384];
  int n = std::snprintf(text, sizeof(text), "%s (%s)\n%.3f mg, %.3f km, slide %.0f%%", wheel.c_str(),
                        wheelStatusName(output.status), output.accumulated_loss_kg * 1e6, output.distance_m * 1e-3,
                        100.0 * output.result.slide_fraction);
  if (inputs != nullptr && n > 0 && n < static_cast<int>(sizeof(text))) {
    // Why it wears: the step's inputs and the wear rate they give.
    std::snprintf(text + n, sizeof(text) - static_cast<std::size_t>(n),
                  "\nFz %.2f kN, alpha %.2f deg, kappa %.4f\nwear %.2f mg/km", inputs->load_n() * 1e-3,
                  inputs->slipAngle_rad() * 180.0 / M_PI, inputs->slipRatio(),
                  output.result.wear_rate_kg_per_m * 1e9);
  }
  label.text = text;
  array->markers.push_back(label);
}

WearMarkers::WearMarkers(const std::vector<std::unique_ptr<WheelPipeline>>& wheels) {
  for (const auto& w : wheels)
    wheels_.push_back({w.get(), std::make_unique<WearModel>(w->tire(), w->modelOptions()), PatchFields()});
}

void WearMarkers::build(const ros::Time& stamp, visualization_msgs::MarkerArray* array) {
  for (Wheel& w : wheels_) {
    const WheelSnapshot s = w.pipeline->snapshot();
    WearResult result = s.output.result;
    if (s.output.evaluated) {
      w.model->setPreset(s.output.preset);
      const BrushWearModel& solver = w.model->solver(s.output.preset);
      w.fields.resize(solver.nodesX(), solver.strips());
      // Empties the fields for a wheel off the ground: then only the label is drawn.
      evaluateInputs(*w.model, s.step_inputs, s.step_time_s, w.pipeline->estimatorParams().stale_timeout_s, &result,
                     &w.fields);
    } else {
      w.fields.resize(0, 0);
    }
    const WheelConfig& c = w.pipeline->config();
    appendWheelMarkers(c.name, c.frame_id, stamp, w.fields, result, s.output, array, &s.step_inputs);
  }
}

}  // namespace tread_wear
