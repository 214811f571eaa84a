#include "pipescope/io/image_source.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

// A test frame of one grey value, with one pixel at the other end of the range so that it is
// not a uniform frame, which ImageSource skips (a black or white frame has nothing to measure).
cv::Mat MarkedImage(int rows, int cols, int type, cv::Scalar value) {
  cv::Mat image(rows, cols, type, value);
  const double top = CV_MAT_DEPTH(type) == CV_16U ? 65535.0 : 255.0;
  image(cv::Rect(0, 0, 1, 1)).setTo(cv::Scalar::all(value[0] < top / 2 ? top : 0.0));
  return image;
}

DatasetManifest FolderManifest(const std::filesystem::path& dir, double fps) {
  DatasetManifest manifest;
  manifest.name = "test";
  manifest.images_dir = dir;
  manifest.fps = fps;
  return manifest;
}

TEST(ImageSource, StreamsSortedFramesConvertingDepthAndColour) {
  const auto dir = MakeTestDirectory("source_depths");
  // Written out of order: frames come back sorted by file name.
  cv::imwrite((dir / "frame_002.png").string(), MarkedImage(4, 6, CV_16UC1, cv::Scalar(65535)));
  cv::imwrite((dir / "frame_000.png").string(), MarkedImage(4, 6, CV_8UC1, cv::Scalar(100)));
  cv::imwrite((dir / "frame_001.tiff").string(),
              MarkedImage(4, 6, CV_8UC3, cv::Scalar(50, 50, 50)));
  WriteTextFileAtomically(dir / "notes.txt", "not an image");

  auto source =
      ImageSource::Open(FolderManifest(dir, 10.0), {.expected_width = 6, .expected_height = 4});
  EXPECT_EQ(source->FrameCount(), 3u);
  const float expected_grey[] = {100.0f, 50.0f, 255.0f};
  for (int i = 0; i < 3; ++i) {
    const std::optional<Frame> frame = source->Next();
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(frame->index, static_cast<std::size_t>(i));
    EXPECT_DOUBLE_EQ(frame->timestamp, i / 10.0);
    EXPECT_EQ(frame->grey.type(), CV_32FC1);
    EXPECT_NEAR(frame->grey.at<float>(2, 3), expected_grey[i], 1e-3);
  }
  EXPECT_FALSE(source->Next().has_value());
}

TEST(ImageSource, NativeDepthAndReadAheadGiveTheSameFrames) {
  const auto dir = MakeTestDirectory("source_native");
  for (int i = 0; i < 5; ++i) {
    cv::imwrite((dir / ("f" + std::to_string(i) + ".png")).string(),
                MarkedImage(4, 6, i % 2 ? CV_16UC1 : CV_8UC1, cv::Scalar(10 * i + 1)));
  }
  auto reference = ImageSource::Open(FolderManifest(dir, 10.0), {.read_ahead = false});
  auto native = ImageSource::Open(FolderManifest(dir, 10.0), {.native_depth = true});
  for (int i = 0; i < 5; ++i) {
    const std::optional<Frame> a = reference->Next();
    const std::optional<Frame> b = native->Next();
    ASSERT_TRUE(a && b);
    EXPECT_EQ(a->name, b->name);
    EXPECT_EQ(b->grey.depth(), i % 2 ? CV_16U : CV_8U);
    const double value = i % 2 ? b->grey.at<std::uint16_t>(1, 2) : b->grey.at<std::uint8_t>(1, 2);
    EXPECT_NEAR(value * GreyLevelsPerUnit(b->grey.depth()), a->grey.at<float>(1, 2), 1e-4);
  }
  EXPECT_FALSE(native->Next().has_value());
  // A source dropped while a frame is being read ahead waits for it.
  auto dropped = ImageSource::Open(FolderManifest(dir, 10.0));
  ASSERT_TRUE(dropped->Next().has_value());
  dropped.reset();
}

TEST(ImageSource, WantedFramesOnlyKeepTheirIndicesAndTimestamps) {
  const auto dir = MakeTestDirectory("source_wanted");
  for (int i = 0; i < 5; ++i) {
    cv::imwrite((dir / ("f" + std::to_string(i) + ".png")).string(),
                MarkedImage(4, 6, CV_8UC1, cv::Scalar(10 * i)));
  }
  // The unwanted frame 3 is not even decoded: an undecodable file there is not reported.
  WriteTextFileAtomically(dir / "f3.png", "this is not a PNG");
  for (const bool read_ahead : {false, true}) {
    ImageSourceOptions options;
    options.read_ahead = read_ahead;
    options.wanted = [](std::size_t index) { return index != 1 && index != 3; };
    auto source = ImageSource::Open(FolderManifest(dir, 10.0), options);
    for (const std::size_t expected : {0u, 2u, 4u}) {
      const std::optional<Frame> frame = source->Next();
      ASSERT_TRUE(frame.has_value());
      EXPECT_EQ(frame->index, expected);
      EXPECT_DOUBLE_EQ(frame->timestamp, 0.1 * static_cast<double>(expected));
      EXPECT_NEAR(frame->grey.at<float>(1, 2), 10.0 * static_cast<double>(expected), 1e-4);
    }
    EXPECT_FALSE(source->Next().has_value());
    EXPECT_TRUE(source->skipped_frames().empty());
  }
}

TEST(ImageSource, SkipsUnreadableFrameAndKeepsTimestampsOfOthers) {
  const auto dir = MakeTestDirectory("source_corrupt");
  cv::imwrite((dir / "a.png").string(), MarkedImage(4, 6, CV_8UC1, cv::Scalar(1)));
  WriteTextFileAtomically(dir / "b.png", "this is not a PNG");
  cv::imwrite((dir / "c.png").string(), MarkedImage(4, 6, CV_8UC1, cv::Scalar(3)));
  WriteTextFileAtomically(dir / "times.txt", "# seconds\n0.5\n0.75\n1.25\n");
  DatasetManifest manifest = FolderManifest(dir, 0.0);
  manifest.timestamps_path = dir / "times.txt";
  auto source = ImageSource::Open(manifest);
  EXPECT_DOUBLE_EQ(source->Next()->timestamp, 0.5);
  const std::optional<Frame> third = source->Next();
  ASSERT_TRUE(third.has_value());
  EXPECT_EQ(third->index, 2u);
  EXPECT_DOUBLE_EQ(third->timestamp, 1.25);
  EXPECT_FALSE(source->Next().has_value());
  ASSERT_EQ(source->skipped_frames().size(), 1u);
  EXPECT_NE(source->skipped_frames()[0].find("b.png"), std::string::npos);
}

TEST(ImageSource, BadInputIsInputError) {
  const auto empty = MakeTestDirectory("source_empty");
  EXPECT_THROW(ImageSource::Open(FolderManifest(empty, 10.0)), InputError);
  EXPECT_THROW(ImageSource::Open(FolderManifest(empty / "missing", 10.0)), InputError);

  const auto dir = MakeTestDirectory("source_size");
  cv::imwrite((dir / "a.png").string(), MarkedImage(4, 6, CV_8UC1, cv::Scalar(1)));
  auto source =
      ImageSource::Open(FolderManifest(dir, 10.0), {.expected_width = 640, .expected_height = 480});
  try {
    source->Next();
    FAIL() << "expected a size mismatch error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("a.png"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("640x480"), std::string::npos);
  }

  WriteTextFileAtomically(dir / "times.txt", "0.1\n0.2\n");
  DatasetManifest wrong_count = FolderManifest(dir, 0.0);
  wrong_count.timestamps_path = dir / "times.txt";
  EXPECT_THROW(ImageSource::Open(wrong_count), InputError);
}

TEST(ImageSource, ReadsVideo) {
  const auto dir = MakeTestDirectory("source_video");
  const auto video = dir / "run.avi";
  {
    cv::VideoWriter writer(video.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 5.0,
                           cv::Size(32, 24), /*isColor=*/true);
    ASSERT_TRUE(writer.isOpened());
    for (int i = 0; i < 4; ++i) writer.write(MarkedImage(24, 32, CV_8UC3, cv::Scalar::all(40 * i)));
  }
  DatasetManifest manifest;
  manifest.name = "video";
  manifest.video_path = video;
  manifest.fps = 5.0;
  auto source = ImageSource::Open(manifest, {.expected_width = 32, .expected_height = 24});
  int count = 0;
  while (std::optional<Frame> frame = source->Next()) {
    EXPECT_DOUBLE_EQ(frame->timestamp, count / 5.0);
    EXPECT_NEAR(cv::mean(frame->grey)[0], 40.0 * count, 3.0);  // MJPEG is lossy
    ++count;
  }
  EXPECT_EQ(count, 4);
  manifest.video_path = dir / "missing.avi";
  EXPECT_THROW(ImageSource::Open(manifest), InputError);
}

TEST(ImageSource, SkipsUniformAndRepeatedFramesNamingThem) {
  const auto dir = MakeTestDirectory("source_unusable");
  cv::Mat texture(48, 64, CV_8UC1);
  cv::randu(texture, 0, 255);
  cv::Mat other = texture.clone();
  cv::flip(texture, other, 1);
  cv::imwrite((dir / "0.png").string(), texture);
  cv::imwrite((dir / "1.png").string(), cv::Mat::zeros(48, 64, CV_8UC1));               // black
  cv::imwrite((dir / "2.png").string(), cv::Mat(48, 64, CV_16UC1, cv::Scalar(65535)));  // white
  cv::imwrite((dir / "3.png").string(), other);
  cv::imwrite((dir / "4.png").string(), other);  // repeated
  cv::imwrite((dir / "5.png").string(), texture);
  auto source = ImageSource::Open(FolderManifest(dir, 10.0));
  std::vector<std::size_t> indices;
  while (std::optional<Frame> frame = source->Next()) indices.push_back(frame->index);
  EXPECT_EQ(indices, (std::vector<std::size_t>{0, 3, 5}));
  std::vector<std::string> skipped;
  for (const std::string& name : source->skipped_frames()) {
    skipped.push_back(std::filesystem::path(name).filename().string());
  }
  EXPECT_EQ(skipped, (std::vector<std::string>{"1.png", "2.png", "4.png"}));
  std::size_t fingerprint = 0;
  EXPECT_NE(UnusableFrameFlaw(cv::Mat::zeros(48, 64, CV_8UC1), &fingerprint).find("uniform"),
            std::string::npos);
  EXPECT_EQ(UnusableFrameFlaw(texture, &fingerprint), "");
  EXPECT_NE(UnusableFrameFlaw(texture, &fingerprint).find("same image"), std::string::npos);
}

}  // namespace
}  // namespace pipescope
