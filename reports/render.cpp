#include "reports/render.hpp"

#include "reports/x_display.hpp"

#include <algorithm>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkLegendBoxActor.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

namespace orthosonar::reports {

Rgb truth_colour() { return {1.0, 1.0, 1.0}; }
Rgb dr_colour() { return {1.0, 0.35, 0.2}; }
Rgb slam_colour() { return {1.0, 0.3, 0.95}; }

Status check_display() {
  const std::string problem = detail::x_display_problem();
  if (!problem.empty()) return Error{"no X display for offscreen VTK rendering (" + problem + "): run under `xvfb-run -a`"};
  return Status::Ok();
}

namespace {

vtkSmartPointer<vtkLookupTable> make_lut(ColourMap map, double lo, double hi) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  const int n = 256;
  lut->SetNumberOfTableValues(n);
  lut->SetRange(lo, hi);
  for (int i = 0; i < n; ++i) {
    const Rgb c = colour_at(map, static_cast<double>(i) / (n - 1));
    lut->SetTableValue(i, c[0], c[1], c[2], 1.0);
  }
  lut->Build();
  return lut;
}

vtkSmartPointer<vtkActor> points_actor(const RenderScene& scene, const RenderConfig& config, vtkLookupTable* lut) {
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToFloat();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(scene.points_W.size()));
  vtkNew<vtkFloatArray> scalars;
  scalars->SetNumberOfValues(static_cast<vtkIdType>(scene.points_W.size()));
  vtkNew<vtkCellArray> verts;
  for (size_t i = 0; i < scene.points_W.size(); ++i) {
    const auto& p = scene.points_W[i];
    const auto id = static_cast<vtkIdType>(i);
    pts->SetPoint(id, p.x(), p.y(), p.z());
    scalars->SetValue(id, scene.scalars.empty() ? p.z() : scene.scalars[i]);
    verts->InsertNextCell(1, &id);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetVerts(verts);
  poly->GetPointData()->SetScalars(scalars);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->SetLookupTable(lut);
  mapper->SetScalarRange(lut->GetRange());
  mapper->ScalarVisibilityOn();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetPointSize(static_cast<float>(config.point_size_px));
  actor->GetProperty()->SetRenderPointsAsSpheres(true);
  return actor;
}

vtkSmartPointer<vtkActor> mesh_actor(const TriangleMesh& mesh, const RenderConfig& config) {
  vtkNew<vtkPoints> pts;
  pts->SetNumberOfPoints(static_cast<vtkIdType>(mesh.vertices.size()));
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    pts->SetPoint(static_cast<vtkIdType>(i), mesh.vertices[i].x(), mesh.vertices[i].y(), mesh.vertices[i].z());
  vtkNew<vtkCellArray> polys;
  for (const auto& t : mesh.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    polys->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetPolys(polys);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.85, 0.9, 0.97);
  actor->GetProperty()->SetOpacity(config.mesh_opacity);
  return actor;
}

vtkSmartPointer<vtkPolyData> polyline(const std::vector<Eigen::Vector3d>& points) {
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell(static_cast<int>(points.size()));
  for (size_t i = 0; i < points.size(); ++i) {
    pts->InsertNextPoint(points[i].x(), points[i].y(), points[i].z());
    lines->InsertCellPoint(static_cast<vtkIdType>(i));
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(pts);
  poly->SetLines(lines);
  return poly;
}

// A filled bar as the legend symbol (a bare line renders as an underscore).
vtkSmartPointer<vtkPolyData> legend_swatch() {
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0.0, 0.0, 0.0);
  pts->InsertNextPoint(1.0, 0.0, 0.0);
  pts->InsertNextPoint(1.0, 0.3, 0.0);
  pts->InsertNextPoint(0.0, 0.3, 0.0);
  vtkNew<vtkCellArray> polys;
  const vtkIdType ids[4] = {0, 1, 2, 3};
  polys->InsertNextCell(4, ids);
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(pts);
  poly->SetPolys(polys);
  return poly;
}

void style_text(vtkTextProperty* p, int size_px, bool bold) {
  p->SetFontSize(size_px);
  p->SetColor(1.0, 1.0, 1.0);
  p->SetBold(bold);
  p->SetShadow(true);
}

}  // namespace

Result<cv::Mat> render_scene(const RenderScene& scene, const Camera& camera, const RenderConfig& config) {
  if (auto s = check_display(); !s) return s.error();
  if (config.width_px < 64 || config.height_px < 64) return Error{"render size must be at least 64x64 px"};
  if (!scene.scalars.empty() && scene.scalars.size() != scene.points_W.size())
    return Error{"render: one scalar per point expected"};

  double lo = 0.0, hi = 1.0;
  if (scene.scalar_range) {
    lo = scene.scalar_range->first;
    hi = scene.scalar_range->second;
  } else if (!scene.points_W.empty()) {
    lo = 1e300;
    hi = -1e300;
    for (size_t i = 0; i < scene.points_W.size(); ++i) {
      const double v = scene.scalars.empty() ? scene.points_W[i].z() : scene.scalars[i];
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (hi - lo < 1e-6) hi = lo + 1e-6;
  auto lut = make_lut(scene.colour_map, lo, hi);

  vtkNew<vtkRenderer> renderer;
  // Mid-tone gradient: dark (low) points and white/yellow (high) ones both stand out.
  renderer->SetBackground(0.30, 0.33, 0.38);
  renderer->SetBackground2(0.55, 0.59, 0.65);
  renderer->GradientBackgroundOn();
  if (!scene.points_W.empty()) renderer->AddActor(points_actor(scene, config, lut));
  if (scene.mesh && !scene.mesh->triangles.empty()) renderer->AddActor(mesh_actor(*scene.mesh, config));
  // Trajectories, legend, colour bar and title go on an overlay layer with the same
  // camera: a track is never hidden by the points mapped around it.
  vtkNew<vtkRenderer> overlay;
  overlay->SetLayer(1);
  overlay->SetActiveCamera(renderer->GetActiveCamera());

  vtkNew<vtkLegendBoxActor> legend;
  int entries = 0;
  for (const auto& t : scene.trajectories) entries += t.points_W.size() >= 2 ? 1 : 0;
  legend->SetNumberOfEntries(entries);
  int entry = 0;
  for (const auto& t : scene.trajectories) {
    if (t.points_W.size() < 2) continue;
    auto poly = polyline(t.points_W);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(poly);
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(t.colour[0], t.colour[1], t.colour[2]);
    actor->GetProperty()->SetLineWidth(static_cast<float>(config.line_width_px));
    actor->GetProperty()->SetLighting(false);
    overlay->AddActor(actor);
    double rgb[3] = {t.colour[0], t.colour[1], t.colour[2]};
    legend->SetEntry(entry++, legend_swatch(), (" " + t.label).c_str(), rgb);
  }
  if (entries > 0) {
    legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    legend->GetPositionCoordinate()->SetValue(0.015, 0.015);
    legend->GetPosition2Coordinate()->SetCoordinateSystemToNormalizedViewport();
    legend->GetPosition2Coordinate()->SetValue(250.0 / config.width_px, 38.0 * entries / config.height_px);
    legend->BorderOn();
    legend->BoxOn();
    legend->GetBoxProperty()->SetColor(0.05, 0.06, 0.08);
    legend->GetBoxProperty()->SetOpacity(0.7);
    legend->GetEntryTextProperty()->SetColor(1.0, 1.0, 1.0);
    legend->GetEntryTextProperty()->SetFontSize(18);
    legend->GetEntryTextProperty()->SetShadow(false);
    overlay->AddViewProp(legend);
  }

  vtkNew<vtkScalarBarActor> bar;
  if (!scene.points_W.empty()) {
    bar->SetLookupTable(lut);
    bar->SetTitle(scene.scalar_title.c_str());
    bar->SetNumberOfLabels(6);
    bar->SetLabelFormat("%.2f");
    bar->SetUnconstrainedFontSize(true);
    style_text(bar->GetTitleTextProperty(), 20, true);
    style_text(bar->GetLabelTextProperty(), 18, false);
    bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    // A fixed pixel width on the right, so the title fits at any render size.
    const double bar_w = 190.0 / config.width_px;
    bar->GetPositionCoordinate()->SetValue(1.0 - bar_w, 0.15);
    bar->SetWidth(bar_w * 0.8);
    bar->SetHeight(0.7);
    bar->SetBarRatio(0.3);
    overlay->AddViewProp(bar);
  }

  vtkNew<vtkTextActor> title;
  if (!scene.title.empty()) {
    title->SetInput(scene.title.c_str());
    style_text(title->GetTextProperty(), 26, true);
    title->SetDisplayPosition(16, config.height_px - 42);
    overlay->AddViewProp(title);
  }

  vtkCamera* cam = renderer->GetActiveCamera();
  cam->SetFocalPoint(camera.focal_point.x(), camera.focal_point.y(), camera.focal_point.z());
  cam->SetPosition(camera.position.x(), camera.position.y(), camera.position.z());
  cam->SetViewUp(camera.view_up.x(), camera.view_up.y(), camera.view_up.z());
  cam->SetParallelProjection(camera.parallel);
  cam->SetParallelScale(camera.parallel_scale_m);
  cam->SetViewAngle(camera.view_angle_deg);
  const double dist = (camera.position - camera.focal_point).norm();
  cam->SetClippingRange(std::max(0.01, dist * 0.01), dist * 10.0 + 100.0);

  vtkNew<vtkRenderWindow> window;
  window->SetDisplayId(detail::shared_x_display());  // not owned by the window; see x_display.hpp
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(config.width_px, config.height_px);
  window->SetNumberOfLayers(2);
  window->AddRenderer(renderer);
  window->AddRenderer(overlay);
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* image = grab->GetOutput();
  int dims[3] = {0, 0, 0};
  image->GetDimensions(dims);
  if (dims[0] != config.width_px || dims[1] != config.height_px) return Error{"render: unexpected framebuffer size"};
  auto* data = static_cast<const unsigned char*>(image->GetScalarPointer());
  cv::Mat out(dims[1], dims[0], CV_8UC3);
  for (int y = 0; y < dims[1]; ++y) {
    // VTK's origin is bottom-left; OpenCV's top-left. RGB -> BGR.
    const unsigned char* src = data + static_cast<size_t>(dims[1] - 1 - y) * static_cast<size_t>(dims[0]) * 3;
    auto* dst = out.ptr<unsigned char>(y);
    for (int x = 0; x < dims[0]; ++x) {
      dst[3 * x + 0] = src[3 * x + 2];
      dst[3 * x + 1] = src[3 * x + 1];
      dst[3 * x + 2] = src[3 * x + 0];
    }
  }
  return out;
}

}  // namespace orthosonar::reports
